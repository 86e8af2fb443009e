"""The world's grid cells as a clusterer's units: every cell a scan's echoes fall in wins (ours).

Marsland, Nehmzow & Shapiro (2000) present a scan to a clusterer whose winning
unit's habituating synapse gives the novelty. Here the units are the world
itself, cut into square cells of side ``c``, and a scan of the ``points``
input (:mod:`novelty.io.scans.points`: the robot's pose and each sector's end point
in the world) wins every cell its echoes fall in: several winners a scan, each
stimulated as the paper's winner through its own synapse, any registered
synapse (:class:`~novelty.maps.habituating_map.HabituatingMap` composes the two).
A wall seen from anywhere falls in the same cells and habituates from every
pass; an object standing where the robot saw free space falls in cells never
hit: novel at first sight, familiar after a few passes.

The cells of a scan (:mod:`novelty.maps.scan_rays`): each sector a ray from the
robot to its end point, or, with a cone width ``arc`` (``"sector"``: as wide
as the angle a sector stands for, the median gap between the scan's
bearings), the rays across its cone, their ends half a cell apart (a sonar's
echo spread over its arc; Moravec & Elfes 1985). A ray with an echo *hits*
the cell of its end point; every ray *passes* the cells of the grid walk
(:mod:`novelty.maps.grid_walk`) from the robot to one cell short of its echo,
or to its end without one. A sector ending beyond ``max_range`` is cut to it
and read as no echo.

Free-space evidence. A cell never hit may be a wall the robot never saw from
this side, or space it has seen through. Each cell counts the scans whose
rays passed it, ``f`` (``passes_``: once a scan; a cell hit and passed in one
scan counts as hit). A hit cell's novelty weighs its synapse's efficacy ``y``
by that evidence:

    v = y (u + (1 - u) (1 - exp(-f / f0)))      evidence="free"                  (1)
    v = y                                       evidence="hits"

so an echo is novel where the robot has seen free space and not got used to
something there (a change), and, weighted ``u`` (``unseen``), where it has
seen nothing. ``y`` is read as the least efficacy within ``tolerance`` cells
(the ``(2t + 1)^2`` cells around the hit cell, itself included: an echo a cell
off a surface the map knows is that surface); a cell not met has an
unhabituated synapse's efficacy. With ``min_passes = m`` a cell passed fewer
than ``m`` times gives ``v = 0``. A scan's novelty is the mean of the ``top``
largest ``v`` over the cells it hits (missing ones counted as 0), a small
object falling in a few of the hundreds of cells a laser scan hits; ``top=None``
takes the mean of them all; a scan with no echo scores 0:

    novelty = (v_(1) + ... + v_(k)) / k         v_(1) >= v_(2) >= ..., k = top     (2)

Learning a scan, after its novelty is taken: the cells it hits are its
winners, each stimulated by the synapse's step (``Synapse.step`` with several
winners) only at the first hit of a visit, a hit after at least ``visit_gap``
scans that did not hit it (the scans of one pass are one encounter; 0: every
hit a step, the paper's one step a scan); with ``neighbours`` the eight cells
around each hit cell learn with it at the synapse's neighbour time constant;
the cells its rays passed gain a pass, ``evidence_lag`` scans later (held in
``pending_`` meanwhile), so that an echo is novel where the robot saw free
space on an earlier pass, not a moment ago while approaching.

The cells are held in tiles of 16 x 16 (:mod:`novelty.maps.tiles`): the units
are the cells of the tiles met, in the order met, at most ``max_cells``; a
scan whose rays would touch more than ``max_scan_cells`` cells is refused.
The defaults are those of ``habituating-map`` (chosen in
studies/maps, :func:`~novelty.maps.habituating_map.habituating_map`).

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of an
environment using habituation. Proc. SAB 2000 (the filter).

Moravec, H. & Elfes, A. (1985). High resolution maps from wide angle sonar.
Proc. IEEE ICRA (cells marked occupied where echoes fall and empty along the
rays: the evidence grid behind (1)).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._component import Component, KernelSpec, StateError, check_array_state, check_int_state
from .._validation import Interval, Options
from .grid_walk import walk_rays
from ..io.scans.points import MAX_COORDINATE, split_points
from .scan_rays import ray_count, scan_rays
from .tiles import TILE_CELLS, TileIndex, cell_of_unit, tile_keys

__all__ = ["WorldCells", "ScanCells", "cell_pack"]

_SHIFT_I, _SHIFT_J = np.int64(1 << 30), np.int64(1 << 31)
#: the offsets of a cell's eight neighbours, in the order of their packed keys
NEIGHBOURS = np.array([(di, dj) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj], dtype=np.int64)


def cell_pack(i, j) -> np.ndarray:
    """Cells (i, j) packed into one int64 each, ``(i + 2^30) 2^32 + j + 2^31``: sorted as (i, j) are."""
    return ((np.asarray(i, dtype=np.int64) + _SHIFT_I) << np.int64(32)) + (np.asarray(j, dtype=np.int64) + _SHIFT_J)


def _unpack(keys) -> np.ndarray:
    keys = np.asarray(keys, dtype=np.int64)
    return np.c_[(keys >> np.int64(32)) - _SHIFT_I, (keys & np.int64(0xFFFFFFFF)) - _SHIFT_J]


class ScanCells:
    """The cells of one scan, as the map reads and learns it (the module docstring).

    Attributes
    ----------
    hits : ndarray of shape (h, 2)
        The cells its echoes fall in, each once, sorted by (i, j).
    passed : ndarray of shape (p, 2)
        The cells its rays' free stretches pass, ray after ray, in order (a cell
        as often as rays pass it).
    neighbours : ndarray of shape (q, 2)
        With ``neighbours``: the cells around the hit cells, none of them hit,
        sorted; else none.
    rays : int
        How many rays it was read as.
    """

    def __init__(self, hits, passed, neighbours, rays):
        self.hits, self.passed, self.neighbours, self.rays = hits, passed, neighbours, rays

    def met(self) -> np.ndarray:
        """Every cell in the order the map meets them (its tiles are made in that order)."""
        return np.concatenate([self.hits, self.passed, self.neighbours])


class WorldCells(Component):
    """Grid cells of the world as the units of a habituating filter, several winners a scan (module docstring; ours).

    Parameters
    ----------
    cell_size : float, default=0.1
        ``c``: the side of a cell (m).
    evidence : {"free", "hits"}, default="free"
        A hit cell's novelty (1): its efficacy weighted by the free space seen
        there, or its efficacy alone.
    free_scale : float, default=2.0
        ``f0`` in (1): the passes at which the weight reaches 1 - 1/e.
    unseen : float in [0, 1], default=0.25
        ``u`` in (1): the weight of a cell never passed.
    top : int or None, default=2
        ``k`` in (2): a scan's novelty is the mean of its ``top`` most novel
        hit cells; None: of all of them.
    tolerance : int, default=1
        Read a hit cell's efficacy as the least within this many cells of it.
    min_passes : float, default=0
        Cells passed fewer times than this give no novelty.
    evidence_lag : int, default=0
        A scan's passes count this many scans later.
    visit_gap : int, default=10
        A hit cell is stimulated only at the first hit of a visit, after at
        least this many scans that did not hit it (0: at every hit).
    arc : float or "sector", default="sector"
        Read each sector as a cone this wide (rad); 0: its axis; ``"sector"``:
        as wide as the median angle between the scan's sectors.
    neighbours : bool, default=False
        The eight cells around each hit cell learn with it (at the synapse's
        ``tau_neighbour``).
    max_range : float, default=10.0
        Sectors ending farther than this from the robot (m) are cut to it and
        read as no echo.
    max_scan_cells : int, default=1000000
        A scan whose rays would touch more cells than this is refused.
    max_cells : int, default=4194304
        The most cells the map holds (whole tiles of 256); cells beyond are
        read as never met and not learned.

    Attributes
    ----------
    tiles_ : ndarray of int64, shape (n_tiles,)
        The keys of the tiles met (:func:`novelty.maps.tiles.tile_keys`), in
        the order met; the units are their cells, 256 a tile.
    passes_ : ndarray of shape (n_units,)
        The scans whose rays passed each cell.
    last_hit_ : ndarray of int64, shape (n_units,)
        The scan (1, 2, ... over all scans learned) that last hit each cell; 0: never.
    scans_ : int
        The scans learned.
    pending_ : ndarray of shape (n_pending, n_features)
        The last scans learned whose passes do not count yet (at most ``evidence_lag``).
    """

    _kind = "clusterer"
    _capabilities = frozenset({"several-winners"})

    _parameter_rules = {
        "cell_size": Interval(numbers.Real, 1e-3, 1e3),
        "evidence": Options(("free", "hits")),
        "free_scale": Interval(numbers.Real, 0, 1e6, closed="right"),
        "unseen": Interval(numbers.Real, 0, 1),
        "top": Interval(numbers.Integral, 1, 10**6, allow_none=True),
        "tolerance": Interval(numbers.Integral, 0, 10),
        "min_passes": Interval(numbers.Real, 0, 2**53),
        "evidence_lag": Interval(numbers.Integral, 0, 10**6),
        "visit_gap": Interval(numbers.Integral, 0, 2**53),
        "arc": (Interval(numbers.Real, 0, np.pi), Options(("sector",))),
        "neighbours": Options((True, False)),
        "max_range": Interval(numbers.Real, 0, MAX_COORDINATE, closed="right"),
        "max_scan_cells": Interval(numbers.Integral, 1, 2**31),
        "max_cells": Interval(numbers.Integral, TILE_CELLS, 2**40),
    }

    _kernel = KernelSpec(
        steps="novelty.maps._cells_kernels",
        params=("cell_size", "evidence", "free_scale", "unseen", "top", "tolerance", "min_passes", "evidence_lag",
                "visit_gap", "arc", "neighbours", "max_range", "max_scan_cells", "max_cells"),
        arrays=("passes_", "last_hit_"),
        counters=("scans_",),
    )

    def __init__(self, cell_size=0.1, evidence="free", free_scale=2.0, unseen=0.25, top=2, tolerance=1,
                 min_passes=0, evidence_lag=0, visit_gap=10, arc="sector", neighbours=False, max_range=10.0,
                 max_scan_cells=1_000_000, max_cells=2**22):
        self.cell_size = cell_size
        self.evidence = evidence
        self.free_scale = free_scale
        self.unseen = unseen
        self.top = top
        self.tolerance = tolerance
        self.min_passes = min_passes
        self.evidence_lag = evidence_lag
        self.visit_gap = visit_gap
        self.arc = arc
        self.neighbours = neighbours
        self.max_range = max_range
        self.max_scan_cells = max_scan_cells
        self.max_cells = max_cells

    # ------------------------------------------------------------------ the state
    def initialize(self, X: np.ndarray) -> "WorldCells":
        """Validate the parameters and start an empty map for rows like ``X`` (the points input)."""
        self._validate_params()
        split_points(X[:1], type(self).__name__, bounded=True)
        self.tiles_ = np.empty(0, dtype=np.int64)
        self.passes_ = np.empty(0)
        self.last_hit_ = np.empty(0, dtype=np.int64)
        self.scans_ = 0
        self.pending_ = np.empty((0, X.shape[1]))
        return self

    @property
    def n_units_(self) -> int:
        return self.tiles_.size * TILE_CELLS

    @property
    def max_tiles(self) -> int:
        """The most tiles the map holds: ``max_cells`` in whole tiles."""
        return int(self.max_cells) // TILE_CELLS

    def _check_state(self) -> None:
        tiles = check_array_state(self, "tiles_", 1, "i")
        n = tiles.size * TILE_CELLS
        passes = check_array_state(self, "passes_", 1, shape=(n,))
        last = check_array_state(self, "last_hit_", 1, "i", shape=(n,))
        scans = check_int_state(self, "scans_")
        check_array_state(self, "pending_", 2)
        if tiles.size > self.max_tiles:
            raise StateError(f"{type(self).__name__} holds {tiles.size} tiles, more than max_cells = "
                             f"{self.max_cells} allows ({self.max_tiles}).")
        if np.any(tiles < 0) or np.unique(tiles).size != tiles.size:
            raise StateError(f"{type(self).__name__}.tiles_ must hold distinct tile keys (novelty.maps.tiles).")
        if n and (last.min() < 0 or last.max() > scans or passes.min() < 0):
            raise StateError(f"{type(self).__name__}.last_hit_ must lie in [0, scans_ = {scans}] (0: never hit) "
                             "and passes_ be >= 0.")

    # ------------------------------------------------------------------ one scan, as the references read it
    def scan_cells(self, x: np.ndarray, walk: bool = True) -> ScanCells:
        """The cells of one scan (a row of the points input), as the map reads and learns them (without
        ``walk``: its hit cells only, what its novelty reads)."""
        c = float(self.cell_size)
        n = (x.shape[0] - 3) // 3
        near, ex, ey = x[3:3 + n], x[3 + n:3 + 2 * n], x[3 + 2 * n:]
        arc = -1.0 if isinstance(self.arc, str) else float(self.arc)
        count = ray_count(x[0], x[1], ex, ey, arc, c, float(self.max_range))
        hit = np.empty(count, dtype=np.bool_)
        end_x, end_y, free_x, free_y = np.empty(count), np.empty(count), np.empty(count), np.empty(count)
        scan_rays(x[0], x[1], near, ex, ey, arc, c, float(self.max_range), c, hit, end_x, end_y, free_x, free_y)
        hits = _unpack(np.unique(cell_pack(np.floor(end_x[hit] / c), np.floor(end_y[hit] / c))))
        if not walk:
            return ScanCells(hits, np.empty((0, 2), dtype=np.int64), np.empty((0, 2), dtype=np.int64), count)
        walked = ~np.isnan(free_x)
        starts = np.broadcast_to(x[:2], (int(walked.sum()), 2))
        passed, _ = walk_rays(starts, np.c_[free_x[walked], free_y[walked]], c)
        around = np.empty((0, 2), dtype=np.int64)
        if self.neighbours and hits.size:
            keys = np.unique(cell_pack(*(hits[:, None, :] + NEIGHBOURS[None, :, :]).reshape(-1, 2).T))
            around = _unpack(np.setdiff1d(keys, cell_pack(hits[:, 0], hits[:, 1]), assume_unique=True))
        return ScanCells(hits, passed, around, count)

    def readout_efficacy(self, hits: np.ndarray, units_of, efficacy: np.ndarray, fresh: float) -> np.ndarray:
        """Each hit cell's efficacy as the map reads it: the least within ``tolerance`` cells of it (a cell not
        held: ``fresh``)."""
        t = int(self.tolerance)
        span = np.arange(-t, t + 1)
        block = np.array([(a, b) for a in span for b in span], dtype=np.int64)
        around = (hits[:, None, :] + block[None, :, :]).reshape(-1, 2)
        units = units_of(around[:, 0], around[:, 1]).reshape(hits.shape[0], -1)
        return np.where(units >= 0, efficacy[np.maximum(units, 0)] if efficacy.size else fresh, fresh).min(axis=1)

    def readout(self, hits: np.ndarray, units_of, efficacy: np.ndarray, fresh: float) -> tuple[np.ndarray, float]:
        """Each hit cell's novelty ``v`` by (1) and the scan's by (2), given how to find a cell's unit
        (``units_of(i, j)``, -1 where not held), the synapses' efficacies and a fresh synapse's."""
        if hits.shape[0] == 0:
            return np.empty(0), 0.0
        y = self.readout_efficacy(hits, units_of, efficacy, fresh)
        own = units_of(hits[:, 0], hits[:, 1])
        f = np.where(own >= 0, self.passes_[np.maximum(own, 0)] if self.passes_.size else 0.0, 0.0)
        v = y.copy()
        if self.evidence == "free":
            u = float(self.unseen)
            weight = np.array([u + (1.0 - u) * -math.expm1(-p / self.free_scale) for p in f.tolist()])
            v = y * weight
        if self.min_passes > 0:
            v = np.where((own >= 0) & (f >= self.min_passes), v, 0.0)
        ranked = np.sort(v)
        k = ranked.size if self.top is None else int(self.top)
        total = 0.0
        for value in ranked[max(ranked.size - k, 0):].tolist():   # one by one, as the compiled loop sums
            total += value
        return v, total / k

    def first_novelty(self, fresh: float) -> float:
        """The novelty of a scan met by an empty map: each cell unseen, novel by a fresh efficacy, weight ``u``."""
        return fresh if self.evidence == "hits" else fresh * float(self.unseen)

    def cells_of_units(self, units: np.ndarray) -> np.ndarray:
        """The cell (i, j) of each unit."""
        return cell_of_unit(units, self.tiles_)

    def index(self) -> TileIndex:
        """The tiles found by key with numpy (:class:`~novelty.maps.tiles.TileIndex`)."""
        return TileIndex(self.tiles_)

    def new_tiles(self, cells: np.ndarray, index: TileIndex) -> np.ndarray:
        """The keys of the tiles of ``cells`` not held, in the order the cells meet them, as many as the map
        has room for."""
        keys = tile_keys(cells[:, 0], cells[:, 1])
        unique, first = np.unique(keys, return_index=True)
        order = unique[np.argsort(first, kind="stable")]
        new = order[index.find(order) < 0]
        return new[:max(self.max_tiles - index.tiles.size, 0)]
