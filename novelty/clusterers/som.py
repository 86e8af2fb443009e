"""Kohonen's self-organising map, in the form Marsland et al. (2000) used.

Units sit on a rectangular ``n_rows x n_columns`` grid. For an input ``v`` the
winner is the unit with the least squared Euclidean distance

    d_j = sum_i (w_ji - v_i)^2                                           (1)

and the winner and every unit within ``radius`` grid steps of it in each
direction (a square neighbourhood: the 8 surrounding units for radius 1) move
towards the input with the same learning rate:

    w_j <- w_j + eta(t) * (v - w_j)                                      (2)

The paper keeps eta = 0.25 and the radius at 1 throughout ("so that the network
was always learning"). ``neighbour_learning_rate`` (ours, not in the paper)
gives the neighbours a rate of their own, eta_n instead of eta(t) in (2) for
every unit but the winner; None, the default, is the paper's shared rate. For users who want a converging map, ``decay`` makes
both fall from their initial to their final values over ``decay_steps``
updates t:

- ``"linear"``:     p(t) = p0 + (p_final - p0) * min(t / T, 1)
- ``"asymptotic"``: p(t) = p_final + (p0 - p_final) / (1 + 2 t / T)

and the grid radius used is p(t) rounded half up to an integer.

References
----------
Kohonen, T. (1993). Self-Organization and Associative Memory, 3rd ed. Springer.

Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of an
environment using habituation. Proc. SAB 2000, section 2, equations (2)-(3).
"""

from __future__ import annotations

import numbers

import numpy as np

from ..distances import squared_distances
from .._component import MAX_COUNT, KernelSpec, StateError, check_int_state
from .._validation import Bounds, Interval, Options
from .base import NO_GROWTH, Clusterer, Growth, Match, move_towards

__all__ = ["SOM", "scheduled"]


def scheduled(decay, start, final, t, steps):
    """A parameter after ``t`` updates under the schedule ``decay`` (0 constant, 1 linear,
    2 asymptotic: the order of the ``decay`` options), as in the module docstring.

    Run by the reference and compiled by the kernels.
    """
    if decay == 0:
        return start
    if decay == 1:
        return start + (final - start) * min(t / steps, 1.0)
    return final + (start - final) / (1.0 + 2.0 * t / steps)


class SOM(Clusterer):
    """A rectangular Kohonen self-organising map (the paper's clusterer).

    Parameters
    ----------
    n_rows : int, default=10
        Rows of the map grid.
    n_columns : int, default=10
        Columns of the map grid.
    learning_rate : float, default=0.25
        eta in equation (2), for the winner and its neighbours alike.
    neighbour_learning_rate : float or None, default=None
        Not in the paper: a constant rate eta_n for the neighbours, the
        winner keeping eta(t). None (the paper) uses eta(t) for both.
    radius : int or float, default=1
        Neighbourhood radius in grid steps (square: Chebyshev distance).
    decay : {"constant", "linear", "asymptotic"}, default="constant"
        How learning rate and radius change with the number of updates.
    decay_steps : int, default=1000
        T in the decay formulas.
    learning_rate_final : float, default=0.01
        Learning rate reached by the decay.
    radius_final : float, default=0.0
        Radius reached by the decay.
    init : {"uniform", "sample"}, default="uniform"
        Initial weights drawn uniformly in ``init_range``, or copied from
        random rows of the first batch.
    init_range : tuple of float, default=(0.0, 1.0)
        Range of the uniform initialisation (the paper's inputs lie in [0, 1]).

    Attributes
    ----------
    weights_ : ndarray of shape (n_rows * n_columns, n_features)
        Unit prototypes, row-major over the grid (unit ``r * n_columns + c``).
    unit_ids_ : ndarray of shape (n_units,)
        Stable ids (equal to the rows: a SOM never grows).
    n_updates_ : int
        Number of inputs learned so far (t in the decay formulas).

    References
    ----------
    Kohonen (1993); Marsland, Nehmzow & Shapiro (2000), equations (2)-(3).

    Examples
    --------
    >>> import numpy as np
    >>> som = SOM(n_rows=2, n_columns=2).initialize(np.zeros((1, 3)), random_state=0)
    >>> som.weights_.shape
    (4, 3)
    >>> m = som.match(np.ones(3))
    >>> sorted(m.neighbours.tolist() + [m.winner])
    [0, 1, 2, 3]
    """

    _parameter_rules = {
        "n_rows": Interval(numbers.Integral, 1, None),
        "n_columns": Interval(numbers.Integral, 1, None),
        "learning_rate": Interval(numbers.Real, 0, 1),
        "neighbour_learning_rate": Interval(numbers.Real, 0, 1, allow_none=True),
        "radius": Interval(numbers.Real, 0, None),
        "decay": Options(("constant", "linear", "asymptotic")),
        "decay_steps": Interval(numbers.Integral, 1, MAX_COUNT),
        "learning_rate_final": Interval(numbers.Real, 0, 1),
        "radius_final": Interval(numbers.Real, 0, None),
        "init": Options(("uniform", "sample")),
        "init_range": Bounds(),
    }

    _capabilities = frozenset({"nearest-unit"})  # match: the first unit of least distance

    _kernel = KernelSpec(
        steps="novelty.clusterers._som_steps",
        params=("n_rows", "n_columns", "learning_rate", "neighbour_learning_rate", "radius",
                "decay", "decay_steps", "learning_rate_final", "radius_final"),
        counters=("n_updates_", "_table_radius"),
        ignores=("init", "init_range"),
    )

    def __init__(
        self,
        n_rows=10,
        n_columns=10,
        learning_rate=0.25,
        radius=1,
        decay="constant",
        decay_steps=1000,
        learning_rate_final=0.01,
        radius_final=0.0,
        init="uniform",
        init_range=(0.0, 1.0),
        neighbour_learning_rate=None,
    ):
        self.n_rows = n_rows
        self.n_columns = n_columns
        self.learning_rate = learning_rate
        self.radius = radius
        self.decay = decay
        self.decay_steps = decay_steps
        self.learning_rate_final = learning_rate_final
        self.radius_final = radius_final
        self.init = init
        self.init_range = init_range
        self.neighbour_learning_rate = neighbour_learning_rate

    # ----------------------------------------------------------- schedules
    def _scheduled(self, start: float, final: float) -> float:
        code = self._parameter_rules["decay"].values.index(self.decay)
        return float(scheduled(code, start, final, self.n_updates_, self.decay_steps))

    def current_learning_rate(self) -> float:
        """eta(t) for the next update."""
        return self._scheduled(self.learning_rate, self.learning_rate_final)

    def current_radius(self) -> int:
        """The integer grid radius for the next update."""
        return int(np.floor(self._scheduled(self.radius, self.radius_final) + 0.5))

    # -------------------------------------------------------------- network
    def _initialize(self, X: np.ndarray, rng: np.random.Generator) -> None:
        n_units = self.n_rows * self.n_columns
        n_features = X.shape[1]
        if self.init == "uniform":
            low, high = self.init_range
            self.weights_ = rng.uniform(low, high, size=(n_units, n_features))
        else:
            self.weights_ = X[rng.integers(0, X.shape[0], size=n_units)].copy()
        self.n_updates_ = 0

    def grid_positions(self) -> np.ndarray:
        """(row, column) on the grid of every unit, shape (n_units, 2)."""
        return np.stack(np.divmod(np.arange(self.n_rows * self.n_columns), self.n_columns), axis=1)

    def _rebuild_scratch(self) -> None:
        # the grid radius in use (the compiled kernels read and return it too)
        self._table_radius = self.current_radius()

    def neighbours_of(self, unit: int, radius: int) -> np.ndarray:
        """Rows of the units within ``radius`` grid steps of ``unit`` (itself excluded), ascending.

        Computed from the grid coordinates: memory and time grow with the
        neighbourhood, not with the map (a table of every unit's neighbours
        would hold n_units**2 entries: 1.6e9 for a 200 x 200 map).
        """
        row, col = divmod(int(unit), self.n_columns)
        rows = np.arange(max(0, row - radius), min(self.n_rows, row + radius + 1))
        cols = np.arange(max(0, col - radius), min(self.n_columns, col + radius + 1))
        block = (rows[:, None] * self.n_columns + cols[None, :]).ravel()
        return block[block != unit]

    def match(self, x: np.ndarray) -> Match:
        d = squared_distances(self.weights_, x)
        winner = int(np.argmin(d))
        return Match(winner, float(d[winner]), self.neighbours_of(winner, self._table_radius))

    def adapt(self, x: np.ndarray, match: Match) -> Growth:
        W = self.weights_
        if self.neighbour_learning_rate is None:
            rows = np.append(match.neighbours, match.winner)
            W[rows] = move_towards(W[rows], x, self.current_learning_rate())
        else:
            W[match.winner] = move_towards(W[match.winner], x, self.current_learning_rate())
            W[match.neighbours] = move_towards(W[match.neighbours], x, self.neighbour_learning_rate)
        self.n_updates_ += 1
        if self.decay != "constant" and self.current_radius() != self._table_radius:
            self._rebuild_scratch()
        return NO_GROWTH

    def _check_state(self) -> None:
        super()._check_state()
        check_int_state(self, "n_updates_")
        self._check_units(self.weights_.shape[0])

    def _check_units(self, n_units: int) -> None:
        # the compiled steps index the grid's neighbourhoods by n_rows and n_columns
        if n_units != self.n_rows * self.n_columns:
            raise StateError(f"SOM.weights_ has {n_units} units; a {self.n_rows} x "
                             f"{self.n_columns} map has {self.n_rows * self.n_columns}.")
