"""The interface of an online competitive network (a "clusterer").

A clusterer holds a set of units, each with a weight vector (a prototype of
the inputs it stands for). For one input it finds the winning unit and the
units that learn with it (:meth:`Clusterer.match`), and adapts to the input
(:meth:`Clusterer.adapt`). Growing networks (GNG, GWR) may add and remove
units while adapting; they report it as a :class:`Growth`, so that the
synapse bank of a novelty filter follows them. Every unit carries a stable id
(``unit_ids_``) that survives the removal of others.

Rows versus ids: methods speak of *rows* (positions in ``weights_``), which
shift when units are removed; ``unit_ids_[row]`` is the stable id.

Shares its name with ``novelty/habituation/base.py``: each kind of component keeps its base classes
beside its modules.
"""

from __future__ import annotations

from abc import abstractmethod
from typing import NamedTuple

import numpy as np

from .._component import Component, StateError, check_array_state, check_int_state
from .._validation import MAX_SCAN_NORM
from .._validation.scans import cleared
from ..distances import squared_distances

__all__ = ["Clusterer", "Match", "Growth", "NO_UNITS", "move_towards"]

NO_UNITS = np.empty(0, dtype=np.intp)
NO_UNITS.setflags(write=False)

#: rows per block in vectorised winner search (bounds memory to ~ rows x units)
_CHUNK_ROWS = 8192


def move_towards(w, x, rate):
    """A prototype ``w`` moved towards the input ``x`` by ``rate``: ``w + rate * (x - w)``.

    The learning step of every clusterer here, for arrays (the reference) and
    for single values (compiled by the kernels, element by element).
    """
    return w + rate * (x - w)



def _largest_norm(W: np.ndarray) -> float:
    """The largest Euclidean norm of the rows of ``W`` (inf where a square overflows)."""
    if W.size == 0:
        return 0.0
    scale = float(np.abs(W).max())
    if scale == 0.0 or not np.isfinite(scale):
        return scale
    return scale * float(np.sqrt(((W / scale) ** 2).sum(axis=1).max()))

class Match(NamedTuple):
    """The outcome of presenting one input, before any learning.

    Attributes
    ----------
    winner : int
        Row of the best-matching unit.
    distance : float
        Squared Euclidean distance from the input to the winner.
    neighbours : ndarray of int
        Rows of the units that learn with the winner (winner excluded).
    runner_up : int
        Row of the second-best unit, for networks that need it (else -1).
    """

    winner: int
    distance: float
    neighbours: np.ndarray
    runner_up: int = -1


class Growth(NamedTuple):
    """Structural changes made by one :meth:`Clusterer.adapt`.

    ``removed`` rows (indices before the removal, sorted) are deleted first;
    then ``added`` new units are appended at the end. ``new_winner``: the
    (last) added unit stands for this input and fires for it, as its winner.
    """

    added: int = 0
    removed: np.ndarray = NO_UNITS
    new_winner: bool = False


NO_GROWTH = Growth()


class Clusterer(Component):
    """An online competitive network (abstract).

    Attributes
    ----------
    weights_ : ndarray of shape (n_units, n_features)
        One prototype per unit.
    unit_ids_ : ndarray of shape (n_units,), dtype int64
        Stable id of each unit.
    next_unit_id_ : int
        The id the next new unit will get.
    """

    _kind = "clusterer"
    #: capabilities this class itself declares (see :func:`novelty._component.declares`):
    #: ``"nearest-unit"`` when the winner is the first unit of least squared distance
    _capabilities: frozenset = frozenset()

    # ---------------------------------------------------------- to implement
    @abstractmethod
    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        """Create the initial units (``weights_``) for inputs like ``X``."""

    @abstractmethod
    def match(self, x: np.ndarray) -> Match:
        """Find the winner of ``x`` and the units that learn with it; no learning."""

    @abstractmethod
    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        """Learn from ``x`` given its :class:`Match`; report added/removed units."""

    # ------------------------------------------------------- optional hooks
    @property
    def uses_match_scale(self) -> bool:
        """Whether the network takes a match scale from :meth:`calibrate`."""
        return False

    def calibrate(self, scale: float | None) -> None:
        """Take the match scale (a distance; None: not known yet) calibrated on the inputs.

        The habituating filter calls this after each change of its match
        scale (:mod:`novelty.match_scale`) when :attr:`uses_match_scale`.
        """

    def assumed_range(self) -> tuple[float, float] | None:
        """The range of input values the network's parameters assume; None: any.

        A network whose units start uniformly in ``init_range``
        (``init="uniform"``, the convention of the built-in networks) assumes
        inputs in that range: on scans far outside it the units start far from
        every scan. The habituating filter warns when its scans lie far
        outside this range. A network with other assumptions says so here.
        """
        if getattr(self, "init", None) == "uniform" and getattr(self, "init_range", None) is not None:
            low, high = self.init_range
            return float(low), float(high)
        return None

    def _check_units(self, n_units: int) -> None:
        """Raise :class:`StateError` if the parameters leave no room for ``n_units`` units (a
        map's grid fixes their number): what the compiled steps index by, checked before they
        run (:mod:`novelty._kernels.state`) and when a model file is read. None by default."""

    def grows_for(self, rows: np.ndarray, distances: np.ndarray) -> np.ndarray | None:
        """Which inputs would be given a new unit of their own if they were learned now.

        ``rows`` and ``distances`` are the inputs' winners and squared
        distances. None (the default): no input is (a network whose
        ``Growth.new_winner`` follows from a poor match must answer).
        """
        return None

    # --------------------------------------------------------------- provided
    def initialize(self, X: np.ndarray, random_state: int | np.random.Generator | None = None) -> "Clusterer":
        """Validate parameters and create the initial units for inputs like ``X``.

        ``X`` is the first batch the network will see (some initialisations
        sample from it); ``random_state`` makes the initialisation reproducible.
        """
        self._validate_params()
        rng = np.random.default_rng(random_state)
        try:
            self._initialize(np.asarray(X, dtype=np.float64), rng)
        except MemoryError as exc:  # numpy says how much it could not allocate
            raise ValueError(f"{type(self).__name__} with these parameters does not fit in memory for "
                             f"{X.shape[1]} features: {exc}. Use fewer units.") from None
        if _largest_norm(self.weights_) > MAX_SCAN_NORM:
            raise ValueError(
                f"{type(self).__name__}'s initial weights reach a norm of {_largest_norm(self.weights_):.3g}, "
                f"beyond {MAX_SCAN_NORM:g}, the largest scan norm (init_range too wide for "
                f"{self.weights_.shape[1]} features)."
            )
        n = self.weights_.shape[0]
        self.unit_ids_ = np.arange(n, dtype=np.int64)
        self.next_unit_id_ = n
        self._rebuild_scratch()
        return self

    @property
    def n_units_(self) -> int:
        return self.weights_.shape[0]

    def learn_one(self, x: np.ndarray) -> tuple[Match, Growth]:
        """Match then adapt to one input."""
        match = self.match(x)
        return match, self.adapt(x, match)

    def winners(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Winning rows and squared distances for many inputs, without learning.

        Vectorised as blocks of ``|x|^2 - 2 x.w + |w|^2``; rows where the best
        two units are within rounding of each other are recomputed directly,
        so the winners equal those of :meth:`match` exactly.
        """
        X = np.asarray(X, dtype=np.float64)
        W = self.weights_
        n = X.shape[0]
        rows = np.empty(n, dtype=np.intp)
        dist = np.empty(n, dtype=np.float64)
        w_sq = np.einsum("ij,ij->i", W, W)
        for start in range(0, n, _CHUNK_ROWS):
            block = X[start : start + _CHUNK_ROWS]
            d = block @ W.T
            d *= -2.0
            d += w_sq
            d += np.einsum("ij,ij->i", block, block)[:, None]
            best = np.argmin(d, axis=1)
            rows[start : start + len(block)] = best
            dist[start : start + len(block)] = d[np.arange(len(block)), best]
            if W.shape[0] > 1:
                self._refine_near_ties(block, d, best, rows[start:], dist[start:])
        np.maximum(dist, 0.0, out=dist)
        return rows, dist

    def _refine_near_ties(self, block, d, best, rows_out, dist_out) -> None:
        # The expanded form loses precision when distances are close; redo those
        # rows with the direct formula that match() uses.
        part = np.partition(d, 1, axis=1)
        scale = np.abs(part[:, :2]).max(axis=1) + np.einsum("ij,ij->i", block, block) + 1.0
        suspect = np.flatnonzero(part[:, 1] - part[:, 0] <= 1e-9 * scale)
        W = self.weights_
        for i in suspect:
            direct = squared_distances(W, block[i])
            j = int(np.argmin(direct))
            rows_out[i] = j
            dist_out[i] = direct[j]

    def quantization_error(self, X: np.ndarray) -> float:
        """Mean Euclidean distance from each input to its winner."""
        _, dist = self.winners(X)
        return float(np.mean(np.sqrt(dist)))

    def _check_norm(self) -> None:
        """Raise :class:`StateError` if a unit lies beyond the norm bound (its distances would
        overflow, and the engines' winners could part ways): learning moves units towards
        scans (convex steps) and initialises them from scans or from init_range, so no unit
        lies beyond the bound scans are held to. Checked with the state, and before every call
        (values written into ``weights_`` in place). A state whose sum of squares is within the
        bound (``cleared``) is within it row by row, without the exact pass."""
        if type(self.weights_) is np.ndarray and cleared(self.weights_):
            return
        if _largest_norm(self.weights_) > MAX_SCAN_NORM * (1 + 1e-9):
            raise StateError(f"{type(self).__name__}.weights_ reach a norm of {_largest_norm(self.weights_):.3g}, "
                             f"beyond the bound {MAX_SCAN_NORM:g} that learning keeps to.")

    def _new_unit_ids(self, n: int) -> np.ndarray:
        ids = np.arange(self.next_unit_id_, self.next_unit_id_ + n, dtype=np.int64)
        self.next_unit_id_ += n
        return ids

    def _check_state(self) -> None:
        W = check_array_state(self, "weights_", 2)
        self._check_norm()
        check_array_state(self, "unit_ids_", 1, "iu", shape=(W.shape[0],))
        nxt = check_int_state(self, "next_unit_id_")
        if W.shape[0] == 0:
            raise StateError(f"{type(self).__name__} has no units.")
        if len(np.unique(self.unit_ids_)) != len(self.unit_ids_) or self.unit_ids_.max() >= nxt:
            raise StateError(f"{type(self).__name__}.unit_ids_ must be unique and below next_unit_id_.")
