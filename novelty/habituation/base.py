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

A subclass provides the model: :meth:`Synapse._advance` integrates the
equation for a set of units over an elapsed time ``dt`` with a constant
stimulus, and ``_per_unit`` / :meth:`Synapse._fresh` describe the per-unit
state so that the bank can grow and shrink with its clusterer.
"""

from __future__ import annotations

from abc import abstractmethod

import numpy as np

from .._component import Component, StateError, check_array_state
from .._validation import Interval, Options

import numbers

__all__ = ["Synapse"]


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

    _common_rules = {
        "tau_winner": Interval(numbers.Real, 0, None, closed="neither"),
        "tau_neighbour": Interval(numbers.Real, 0, None, closed="neither"),
        "others": Options(("hold", "forget")),
        "tau_forget": Interval(numbers.Real, 0, None, closed="neither", allow_none=True),
    }

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

    def step(self, winner: int, neighbours: np.ndarray, stimulus: float = 1.0, dt: float = 1.0) -> None:
        """One time step: habituate the winner and its neighbours.

        Parameters
        ----------
        winner : int
            Row of the winning unit.
        neighbours : ndarray of int
            Rows of the units that learn with it (the winner excluded).
        stimulus : float, default=1.0
            The stimulus S presented to the winner and the neighbours.
        dt : float, default=1.0
            Elapsed time; one scan is one step.
        """
        if self.others == "forget":
            rest = np.ones(self.n_units_, dtype=bool)
            rest[winner] = False
            rest[neighbours] = False
            rows = np.flatnonzero(rest)
            if rows.size:
                tau = self.tau_neighbour if self.tau_forget is None else self.tau_forget
                self._advance(rows, 0.0, tau, dt)
        if len(neighbours):
            self._advance(np.asarray(neighbours, dtype=np.intp), stimulus, self.tau_neighbour, dt)
        self._advance(np.array([winner], dtype=np.intp), stimulus, self.tau_winner, dt)

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
