"""An occupancy grid as a change detector: the baseline a roboticist would set against a habituating map.

The world is cut into square cells of side ``c``; each holds the log-odds
``l`` that it is occupied, 0 (even odds) until a ray meets it (Moravec & Elfes
1985; Thrun, Burgard & Fox 2005, chapter 9, the log-odds form of table 9.1).
A scan of the ``points`` input (:mod:`novelty.io.scans.points`: the robot's pose
and each sector's end point in the world) is read as one beam per sector, from
the robot to its end point (:mod:`novelty.maps.scan_rays`; a sector ending
beyond ``max_range`` is cut to it and read as no echo). The inverse sensor
model updates each cell the scan reaches once:

    l <- min(l_max, l + l_occ)     a cell holding an echo of the scan              (1)
    l <- max(l_min, l + l_free)    a cell a beam passed through, holding none      (2)

(the cells of each beam by the grid walk of :mod:`novelty.maps.grid_walk`, the
echo's own cell excepted; a beam with no echo frees its whole length). The
defaults are the usual ones: ``l_occ = 0.85`` and ``l_free = -0.4``, the log-odds
of an echo read as occupied with probability 0.7 and a pass as free with 0.6,
clamped to ``[-2, 3.5]`` (probabilities 0.12 and 0.97) as OctoMap does (Hornung
et al. 2013), so that a cell that changes can change back.

A scan's novelty is the evidence that the world changed where the grid knew
it, the two tests of the change detectors of mobile robotics (Meyer-Delius,
Beinhofer & Burgard 2012; the binary-map comparison Luft, Schaefer, Schubert
& Burgard 2018 set their posterior method against): an echo landing in a cell
the grid holds free (``l < free_below``, and so every cell within
``tolerance`` cells of it, so that an echo a cell off a known wall is that
wall), and a beam passing through a cell the grid holds occupied (``l >
occupied_above``; the cells within ``tolerance`` of its own echo left out).
With ``evidence="free"`` the novelty is the share of the scan's echoes that
land in free cells; with ``"occupied"`` the share of its beams that pass
through occupied cells; with ``"both"`` the share of its beams that show
either:

    novelty = (beams contradicting the grid) / (beams that could)              (3)

in [0, 1], 0 for a scan with nothing to compare (no echo, with ``"free"``).
``free_below`` sets how much evidence "free" needs: -1 takes three passes
unopposed (``l_free = -0.4``); any value in (-0.4, 0), one.

Learning, each scan is scored against the grid as it was, then learned; a
grid fitted and then only scored is the frozen form (the hold-out protocol's,
or ``policy="frozen"`` on an exploration). The grid holds its cells in tiles
(:mod:`novelty.maps.tiles`), at most ``max_cells``; a scan whose beams would
touch more than ``max_scan_cells`` cells is refused before anything is
learned. The loop is compiled (:mod:`novelty.baselines._occupancy_kernels`).

References
----------
Moravec, H. & Elfes, A. (1985). High resolution maps from wide angle sonar.
Proc. IEEE ICRA, 116-121.

Thrun, S., Burgard, W. & Fox, D. (2005). Probabilistic Robotics. MIT Press,
chapter 9 (occupancy grid mapping; the log-odds update, table 9.1).

Hornung, A., Wurm, K. M., Bennewitz, M., Stachniss, C. & Burgard, W. (2013).
OctoMap: an efficient probabilistic 3D mapping framework based on octrees.
Autonomous Robots, 34(3), 189-206 (clamping).

Meyer-Delius, D., Beinhofer, M. & Burgard, W. (2012). Occupancy grid models
for robot mapping in changing environments. Proc. AAAI, 2024-2030.

Luft, L., Schaefer, A., Schubert, T. & Burgard, W. (2018). Detecting changes
in the environment based on full posterior distributions over real-valued
grid maps. IEEE Robotics and Automation Letters, 3(2), 1299-1305.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np

from .._component import StateError, check_array_state, check_int_state
from .._validation import Interval, Options
from ..detector import NoveltyDetector
from ..io.scans.points import MAX_COORDINATE, example_rows, split_points
from ..maps.tiles import TILE_CELLS, GridFullWarning, TileIndex

__all__ = ["OccupancyGrid"]

#: tiles the arrays start with room for
_FIRST_TILES = 16


class OccupancyGrid(NoveltyDetector):
    """A log-odds occupancy grid whose novelty is the evidence that a scan contradicts it (module docstring).

    Parameters
    ----------
    cell_size : float, default=0.1
        ``c``: the side of a cell (m).
    evidence : {"free", "occupied", "both"}, default="free"
        What contradicts the grid (3): echoes in free cells, beams through
        occupied cells, or either.
    free_below : float, default=-1.0
        A cell is free where its log-odds are below this.
    occupied_above : float, default=0.0
        A cell is occupied where its log-odds are above this.
    tolerance : int, default=1
        Cells around an echo that must be free too (and that a beam may pass
        through occupied) for it to count.
    l_occ : float, default=0.85
        The log-odds an echo adds to its cell (1).
    l_free : float, default=-0.4
        The log-odds a pass adds to a cell (2).
    l_min, l_max : float, default=-2.0, 3.5
        The clamp of every cell's log-odds.
    max_range : float, default=10.0
        Sectors ending farther than this from the robot (m) are cut to it and
        read as no echo.
    max_scan_cells : int, default=1000000
        A scan whose beams would touch more cells than this is refused.
    max_cells : int, default=4194304
        The most cells the grid holds (whole tiles of 256); cells beyond are
        read as unknown and not learned.
    threshold : float, default=0.5
        Novelty above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"

    Attributes
    ----------
    tiles_ : ndarray of int64, shape (capacity,)
        The keys of the tiles held (:func:`novelty.maps.tiles.tile_keys`), in
        the order they were made; -1 beyond ``n_tiles_`` (room for more).
    n_tiles_ : int
        The tiles held.
    log_odds_ : ndarray of shape (capacity * 256,)
        Each cell's log-odds, a tile's 256 cells at a time (0: unknown).
    scans_ : int
        The scans learned.
    n_features_in_ : int

    Examples
    --------
    A corridor with walls at y = +-1 m, seen from x = 0.05 to the left and the
    right twice; then a box 0.5 m to the left, where the grid holds free
    space (three passes, log-odds -1.2), and the wall again:

    >>> row = lambda y_left: [0.05, 0.05, 0.0, 0.5, 0.5, 0.05, 0.05, y_left, -1.0]
    >>> grid = OccupancyGrid(free_below=-1.0, tolerance=0).fit([row(1.0)] * 3)
    >>> grid.novelty([row(1.0), row(0.5)]).tolist()   # one of the two echoes in free space
    [0.0, 0.5]
    """

    #: the rows it reads: the ``points`` input (:mod:`novelty.io.scans.points`)
    input_layout = "points"

    _parameter_rules = {
        "cell_size": Interval(numbers.Real, 1e-3, 1e3),
        "evidence": Options(("free", "occupied", "both")),
        "free_below": Interval(numbers.Real, None, 0, closed="right"),
        "occupied_above": Interval(numbers.Real, 0, None, closed="left"),
        "tolerance": Interval(numbers.Integral, 0, 10),
        "l_occ": Interval(numbers.Real, 0, 100, closed="right"),
        "l_free": Interval(numbers.Real, -100, 0, closed="left"),
        "l_min": Interval(numbers.Real, -1000, 0, closed="left"),
        "l_max": Interval(numbers.Real, 0, 1000, closed="right"),
        "max_range": Interval(numbers.Real, 0, MAX_COORDINATE, closed="right"),
        "max_scan_cells": Interval(numbers.Integral, 1, 2**31),
        "max_cells": Interval(numbers.Integral, TILE_CELLS, 2**40),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, cell_size=0.1, evidence="free", free_below=-1.0, occupied_above=0.0, tolerance=1,
                 l_occ=0.85, l_free=-0.4, l_min=-2.0, l_max=3.5, max_range=10.0, max_scan_cells=1_000_000,
                 max_cells=2**22, threshold=0.5, contamination="auto"):
        self.cell_size = cell_size
        self.evidence = evidence
        self.free_below = free_below
        self.occupied_above = occupied_above
        self.tolerance = tolerance
        self.l_occ = l_occ
        self.l_free = l_free
        self.l_min = l_min
        self.l_max = l_max
        self.max_range = max_range
        self.max_scan_cells = max_scan_cells
        self.max_cells = max_cells
        self.threshold = threshold
        self.contamination = contamination

    @classmethod
    def _example_rows(cls, seed: int = 0, n: int = 120) -> np.ndarray:
        """Rows of the points input for generic checks (:func:`novelty.io.scans.points.example_rows`)."""
        return example_rows(seed, n)

    def _first_novelty(self) -> float:
        return 0.0   # an empty grid: nothing known, nothing contradicted

    def _novelty_bounds(self) -> tuple[float, float]:
        return 0.0, 1.0

    # ------------------------------------------------------------------ learning and scoring
    def _start(self, X: np.ndarray) -> None:
        split_points(X[:1], type(self).__name__)
        room = min(_FIRST_TILES, self._max_tiles())
        self.tiles_ = np.full(room, -1, dtype=np.int64)
        self.n_tiles_ = 0
        self.log_odds_ = np.zeros(room * TILE_CELLS)
        self.scans_ = 0

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        out = self._run(X, learn=True)
        self.scans_ += X.shape[0]
        return out

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        return self._run(X, learn=False)

    def _run(self, X: np.ndarray, learn: bool) -> np.ndarray:
        # numba's import and the kernels' loading cost about a second: paid when a grid first learns or
        # scores, not when the module is read (``novelty list`` reads every detector's docstring)
        from . import _occupancy_kernels as kernels

        n = self._check_rows(X)
        longest = self._check_sizes(X, n)
        self._check_layout()
        table, bits, stamp, counters = self._scratch()
        counters[kernels.PASSED] = 0
        out = np.zeros(X.shape[0])
        done = 0
        evidence = ("free", "occupied", "both").index(self.evidence)
        while True:
            done = kernels.run(X, done, n, float(self.cell_size), float(self.max_range), longest + 2, learn,
                               float(self.l_occ), float(self.l_free), float(self.l_min), float(self.l_max),
                               evidence, float(self.free_below), float(self.occupied_above), int(self.tolerance),
                               self.tiles_, table, bits, self.log_odds_, stamp, counters,
                               self._max_tiles(), out)
            vars(self)["n_tiles_"] = int(counters[kernels.N_TILES])
            self._held(table, bits, stamp, counters)
            if done == X.shape[0]:
                break
            table, bits, stamp = self._grow(int(counters[kernels.NEED]), counters)
        if counters[kernels.PASSED]:
            warnings.warn(f"{type(self).__name__} holds max_cells = {self.max_cells} cells: "
                          f"{int(counters[kernels.PASSED])} cells beyond them were read as unknown and not "
                          "learned (raise max_cells, or cell_size).", GridFullWarning, stacklevel=4)
        return out

    def _max_tiles(self) -> int:
        return int(self.max_cells) // TILE_CELLS

    def _grow(self, tiles: int, counters) -> tuple:
        """Room for at least ``tiles`` tiles (at least twice as many as now, at most ``max_cells``)."""
        capacity = min(max(tiles, 2 * self.tiles_.size), self._max_tiles())
        grown = np.full(capacity, -1, dtype=np.int64)
        grown[:self.tiles_.size] = self.tiles_
        log_odds = np.zeros(capacity * TILE_CELLS)
        log_odds[:self.log_odds_.size] = self.log_odds_
        self.tiles_, self.log_odds_ = grown, log_odds
        vars(self).pop("_grid_scratch", None)
        table, bits, stamp, _ = self._scratch(counters)
        return table, bits, stamp

    def _scratch(self, counters=None) -> tuple:
        """The hash table of the tiles (:mod:`novelty.maps.grid_kernels`), the per-scan stamps and the
        kernels' counters: made again when the tiles were replaced or their count set since."""
        from . import _occupancy_kernels as kernels
        from ..maps import grid_kernels as grid

        held = vars(self).get("_grid_scratch")
        if held is not None and held[0] == self._scratch_key():
            return held[1]
        bits = grid.bits_for(self.tiles_.size)
        counters = np.zeros(4, dtype=np.int64) if counters is None else counters
        counters[kernels.N_TILES] = self.n_tiles_
        scratch = (grid.table_of(self.tiles_, self.n_tiles_, bits), bits,
                   np.zeros(self.log_odds_.size, dtype=np.int64), counters)
        self._held(*scratch)
        return scratch

    def _held(self, *scratch) -> None:
        vars(self)["_grid_scratch"] = (self._scratch_key(), scratch)

    def _scratch_key(self) -> tuple:
        return id(self.tiles_), self.tiles_.size, self.n_tiles_, id(self.log_odds_)

    # ------------------------------------------------------------------ checks
    def _check_rows(self, X: np.ndarray) -> int:
        return split_points(X, type(self).__name__, bounded=True)[2].shape[1]

    def _check_sizes(self, X: np.ndarray, n: int) -> int:
        """Refuse a scan that would touch more than ``max_scan_cells`` cells, before anything is learned;
        warn of sectors cut at ``max_range``. Returns the longest walk of a ray (cells)."""
        from ..maps import grid_kernels as grid

        return grid.check_costs(X, self, 0.0, 0.0, what="beams")[1]

    def _check_layout(self) -> None:
        """What the compiled loop indexes by, checked before every call (a state set or replaced since)."""
        tiles = check_array_state(self, "tiles_", 1, "i")
        check_array_state(self, "log_odds_", 1, shape=(tiles.size * TILE_CELLS,))
        n = check_int_state(self, "n_tiles_", high=tiles.size)
        if tiles.dtype != np.int64 or not tiles.flags.c_contiguous or not self.log_odds_.flags.c_contiguous \
                or not tiles.flags.writeable or not self.log_odds_.flags.writeable:
            self.tiles_ = np.ascontiguousarray(tiles, dtype=np.int64).copy()
            self.log_odds_ = np.ascontiguousarray(self.log_odds_).copy()
        if tiles.size > self._max_tiles() or n > self._max_tiles():
            raise StateError(f"{type(self).__name__} holds room for {tiles.size} tiles, more than max_cells = "
                             f"{self.max_cells} allows ({self._max_tiles()}).")

    def _check_state(self) -> None:
        super()._check_state()
        self._check_layout()
        check_int_state(self, "scans_")
        tiles = self.tiles_[:self.n_tiles_]
        if np.any(tiles < 0) or np.unique(tiles).size != tiles.size or np.any(self.tiles_[self.n_tiles_:] != -1):
            raise StateError(f"{type(self).__name__}.tiles_ must hold n_tiles_ = {self.n_tiles_} distinct keys, "
                             "then -1.")
        low, high = self.log_odds_.min(initial=0.0), self.log_odds_.max(initial=0.0)
        if low < min(self.l_min, 0.0) - 1e-9 or high > max(self.l_max, 0.0) + 1e-9:
            raise StateError(f"{type(self).__name__}.log_odds_ must lie in [l_min, l_max] = [{self.l_min:g}, "
                             f"{self.l_max:g}]; it holds values from {low:.6g} to {high:.6g}.")
        if (self.n_features_in_ - 3) % 3 or self.n_features_in_ < 6:
            raise StateError(f"{type(self).__name__}.n_features_in_ must be 3 + 3n (the 'points' input); "
                             f"got {self.n_features_in_}.")

    # ------------------------------------------------------------------ reading the grid
    def log_odds(self, cells) -> np.ndarray:
        """The log-odds of cells (i, j) (an array of shape (m, 2)); 0 where the grid holds nothing.

        >>> grid = OccupancyGrid(cell_size=1.0).fit([[0.5, 0.5, 0.0, 0.5, 2.5, 0.5]])
        >>> grid.log_odds([[0, 0], [1, 0], [2, 0], [3, 0]]).tolist()   # free, free, the echo, unknown
        [-0.4, -0.4, 0.85, 0.0]
        """
        self._check_fitted()
        cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
        units = TileIndex(self.tiles_[:self.n_tiles_]).units(cells[:, 0], cells[:, 1])
        return np.where(units >= 0, self.log_odds_[np.maximum(units, 0)], 0.0)
