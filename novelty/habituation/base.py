"""The interface of a bank of habituating synapses, one per clustering unit.

Every unit of a clusterer connects to the output neuron through a synapse
whose efficacy ``y`` falls when the unit fires (habituation) and, optionally,
recovers when it does not (forgetting). The efficacy of the winner's synapse
is the novelty of the input (Marsland, Nehmzow & Shapiro 2000, section 2).

One :meth:`Synapse.step` presents a stimulus ``S`` to the winner (time
constant ``tau_winner``) and to its neighbours (``tau_neighbour``). The other
units follow the rule ``others``:

- ``"hold"``: they receive no input and keep their value (the paper's choice);
- ``"forget"``: they receive ``S = 0`` and recover towards ``y0`` with time
  constant ``tau_forget`` (``tau_neighbour`` when None).

The schedule (who is stimulated, with which time constant, and when) is the
base class's, here and in the compiled loop (:mod:`._schedule`); so are its
four parameters (:data:`SCHEDULE`): a subclass whose ``__init__`` does not
take one of them gets it, as a keyword argument with its default and its
rule, from this class. A subclass provides only the model:
:meth:`Synapse._advance` integrates the equation for a set of units over an
elapsed time ``dt`` with a constant stimulus, and ``_per_unit`` /
:meth:`Synapse._fresh` describe the per-unit state so that the bank can grow
and shrink with its clusterer.

Shares its name with ``novelty/clusterers/base.py``: each kind of component keeps its base classes
beside its modules.
"""

from __future__ import annotations

import functools
import inspect
import numbers
from abc import abstractmethod

import numpy as np

from .._component import Component, StateError, check_array_state
from .._validation import Interval, Options

__all__ = ["Synapse", "SCHEDULE"]

#: the parameters of the schedule, which every synapse takes, with their defaults (the paper's)
SCHEDULE = {"tau_winner": 3.33, "tau_neighbour": 14.3, "others": "hold", "tau_forget": None}

_SCHEDULE_RULES = {
    "tau_winner": Interval(numbers.Real, 0, None, closed="neither"),
    "tau_neighbour": Interval(numbers.Real, 0, None, closed="neither"),
    "others": Options(("hold", "forget")),
    "tau_forget": Interval(numbers.Real, 0, None, closed="neither", allow_none=True),
}


def _with_schedule(init, missing: list[str]):
    """``init`` also taking the schedule's parameters ``missing``, as keywords with defaults
    (its signature says so, so that ``get_params``, ``set_params`` and ``clone`` see them)."""

    @functools.wraps(init)
    def __init__(self, *args, **kwargs):
        schedule = {name: kwargs.pop(name, SCHEDULE[name]) for name in missing}
        init(self, *args, **kwargs)
        for name, value in schedule.items():
            setattr(self, name, value)

    signature = inspect.signature(init)
    params = list(signature.parameters.values())
    at = next((i for i, p in enumerate(params) if p.kind is p.VAR_KEYWORD), len(params))
    added = [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=SCHEDULE[name])
             for name in missing]
    __init__.__signature__ = signature.replace(parameters=params[:at] + added + params[at:])
    return __init__


class Synapse(Component):
    """A bank of habituating synapses (abstract).

    Attributes
    ----------
    efficacy_ : ndarray of shape (n_units,)
        Current efficacy of each unit's synapse; the novelty a unit reports.
    """

    _kind = "synapse"
    #: names of the per-unit state arrays (grown and shrunk together)
    _per_unit: tuple[str, ...] = ("efficacy_",)

    #: the rules of the schedule's parameters (:data:`SCHEDULE`); a subclass's own rules are
    #: added to them
    _common_rules = _SCHEDULE_RULES
    _parameter_rules = _SCHEDULE_RULES
    #: the compiled schedule (:mod:`._schedule`) reads them from every synapse's record
    _kernel_base_params = tuple(SCHEDULE)

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        rules = cls.__dict__.get("_parameter_rules")
        if rules is not None and not set(SCHEDULE) <= set(rules):
            cls._parameter_rules = {**{k: v for k, v in _SCHEDULE_RULES.items() if k not in rules},
                                    **rules}
        init = cls.__dict__.get("__init__")
        if init is not None:
            taken = inspect.signature(init).parameters
            missing = [name for name in SCHEDULE if name not in taken]
            if missing:
                cls.__init__ = _with_schedule(init, missing)

    @property
    def schedule(self) -> tuple[float, float, float, bool]:
        """``(tau_winner, tau_neighbour, tau_forget, forget)`` as the schedule reads them:
        ``tau_forget`` is ``tau_neighbour`` when None; ``forget`` is ``others == "forget"``."""
        tau_forget = self.tau_neighbour if self.tau_forget is None else self.tau_forget
        return (float(self.tau_winner), float(self.tau_neighbour), float(tau_forget),
                self.others == "forget")

    # --------------------------------------------------------------- the model
    @abstractmethod
    def _advance(self, rows: np.ndarray, stimulus: float, tau: float, dt: float) -> None:
        """Integrate the model for ``rows`` over ``dt`` under a constant stimulus."""

    @abstractmethod
    def _fresh(self, n: int) -> dict[str, np.ndarray]:
        """State arrays (one entry per name in ``_per_unit``) for ``n`` new units."""

    @property
    @abstractmethod
    def resting_efficacy(self) -> float:
        """The efficacy a synapse settles at under a constant stimulus S = 1."""

    def efficacy_range(self, stimulus: float = 1.0) -> tuple[float, float]:
        """The interval no efficacy leaves while every stimulus lies in ``[0, stimulus]``.

        A model file whose efficacies lie outside it was tampered with, and is
        refused (:meth:`check_efficacy`, called by the component that presents
        the stimulus). A model that bounds its efficacy says so here; the
        default bounds nothing.
        """
        return -np.inf, np.inf

    def check_efficacy(self, stimulus: float = 1.0) -> None:
        """Raise :class:`StateError` if an efficacy lies outside :meth:`efficacy_range`.

        A relative slack of 1e-9 allows for rounding.
        """
        low, high = self.efficacy_range(stimulus)
        y = self.efficacy_
        slack = 1e-9 * max(1.0, abs(low) if np.isfinite(low) else 0.0, abs(high) if np.isfinite(high) else 0.0)
        if y.size and (y.min() < low - slack or y.max() > high + slack):
            raise StateError(
                f"{type(self).__name__}.efficacy_ must lie in [{low:.6g}, {high:.6g}] "
                f"(stimulus {stimulus:g}); it holds values from {y.min():.6g} to {y.max():.6g}."
            )

    # ---------------------------------------------------------------- the bank
    def initialize(self, n_units: int) -> "Synapse":
        """Validate the parameters and create ``n_units`` unhabituated synapses."""
        self._validate_params()
        for name, values in self._fresh(int(n_units)).items():
            setattr(self, name, values)
        return self

    @property
    def n_units_(self) -> int:
        return self.efficacy_.shape[0]

    def step(self, winner, neighbours: np.ndarray, stimulus: float = 1.0, dt: float = 1.0) -> None:
        """One time step: habituate the winner (or winners) and the neighbours.

        Parameters
        ----------
        winner : int or ndarray of int
            Row of the winning unit; or the rows of several winners (a map's
            cells hit by one scan: :mod:`novelty.maps.cells`), each stimulated
            as a winner.
        neighbours : ndarray of int
            Rows of the units that learn with it (no winner among them).
        stimulus : float, default=1.0
            The stimulus S presented to the winner and the neighbours.
        dt : float, default=1.0
            Elapsed time; one scan is one step.
        """
        tau_winner, tau_neighbour, tau_forget, forget = self.schedule
        winners = np.array(winner, dtype=np.intp, ndmin=1)
        if forget:
            rest = np.ones(self.n_units_, dtype=bool)
            rest[winners] = False
            rest[neighbours] = False
            rows = np.flatnonzero(rest)
            if rows.size:
                self._advance(rows, 0.0, tau_forget, dt)
        if len(neighbours):
            self._advance(np.asarray(neighbours, dtype=np.intp), stimulus, tau_neighbour, dt)
        if winners.size:
            self._advance(winners, stimulus, tau_winner, dt)

    def fire(self, row: int, stimulus: float = 1.0, dt: float = 1.0) -> None:
        """Habituate the synapse at ``row`` alone, as a winner's (``tau_winner``); the others are left as they are.

        A growing network's new unit fires for the input that created it.
        """
        self._advance(np.array([row], dtype=np.intp), stimulus, self.tau_winner, dt)

    @property
    def fresh_efficacy(self) -> float:
        """The efficacy of an unhabituated synapse (a new unit's)."""
        return float(self._fresh(1)["efficacy_"][0])

    def grow(self, n: int) -> None:
        """Append ``n`` unhabituated synapses (new units of a growing network)."""
        if n <= 0:
            return
        fresh = self._fresh(n)
        for name in self._per_unit:
            setattr(self, name, np.concatenate([getattr(self, name), fresh[name]]))

    def shrink(self, rows: np.ndarray) -> None:
        """Remove the synapses at ``rows`` (units the network deleted)."""
        rows = np.asarray(rows, dtype=np.intp)
        if rows.size == 0:
            return
        for name in self._per_unit:
            setattr(self, name, np.delete(getattr(self, name), rows, axis=0))

    def _check_state(self) -> None:
        n = check_array_state(self, "efficacy_", 1).shape[0]
        for name in self._per_unit:
            if check_array_state(self, name, 1).shape[0] != n:
                raise StateError(f"{type(self).__name__}.{name} does not have {n} units.")
