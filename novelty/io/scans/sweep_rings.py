"""Sweeps to rings: a sweep's beams seen from the base frame's origin, cut into sectors and reduced.

:func:`sweep_ring` reduces a sweep (:class:`~novelty.io.ros.messages.Sweep`)
to the paper's ring:

- each beam's end point is ``origin + range * (cos angle, sin angle)``; its
  bearing from the base frame's origin is ``atan2`` of the end point and its
  range ``hypot`` (a beam with ``+inf`` keeps its own direction and ``+inf``;
  NaN stays NaN);
- the bearings are cut into sectors and each sector's beams reduced as
  :func:`novelty.io.scans.sectors.sector_index` and
  :func:`novelty.io.scans.sectors.reduce_sectors` do. Where every origin is
  zero the bearings are the beams' own angles, and the ring is exactly
  :func:`laser_ring`'s.

Where a sensor is not at the base frame's origin, a sector's reduced range
is the distance from the robot's centre to what the beams hit, as a sonar
at the centre would report it; the default ``limits`` are then the span of
the beams' directions, and a beam whose end point's bearing falls outside
them is left out.

:class:`RingMaker` is :func:`sweep_ring` with its parameters fixed: it
keeps what a geometry (the beams' directions, and their origins) needs, so
that a recording's sweeps, which share a few geometries, cost a few vector
operations each:

- **origins all zero** (a centred sensor): each beam's sector is its
  direction's, worked out once; the ring is each sector's reduction (the
  nearest range in one ``fmin.reduceat`` over the beams in sector order);
- **offset origins** (a sensor off the centre): a beam's end point ``e = o +
  r u`` is ``|e| = sqrt(r (r + 2 o.u) + |o|^2)`` from the centre (the nearest
  of each sector in one compiled pass: :mod:`novelty.io.scans._sweep_kernels`), and its
  bearing differs from the beam's direction ``u`` by at most ``asin(|o| /
  (r - |o|))`` (``e x u = o x u`` and ``|e| >= r - |o|``). A beam farther
  than ``|o| + |o| / sin(m)`` along, where ``m`` is its direction's angle to
  the nearest sector boundary, stays in its direction's sector; only the
  others (near a boundary, or close to the sensor) have their bearings
  computed (``atan2``). The result is the end points' ring exactly, as
  :func:`reference_ring` computes it for every beam (tested).
"""

from __future__ import annotations

import math

import numpy as np

from ..ros.messages import LaserScan, Sweep
from .ranges import clean_ranges
from .sectors import _check_reduce, _checked_limits, _sectors_within, reduce_sectors, scan_limits, sector_index

__all__ = ["RingMaker", "sweep_ring", "laser_ring", "reference_ring"]


class RingMaker:
    """:func:`sweep_ring` with its parameters fixed, keeping the sectors of the geometries it has met.

    The beams' sectors depend on their directions alone where every origin
    is zero: they are worked out once for a geometry (the same ``angles``
    array, or equal ones) and reused.
    """

    def __init__(self, n_sectors: int = 16, reduce="min", limits=None, front: float = 0.0,
                 clip: float | None = None):
        _check_reduce(reduce)
        self.n_sectors, self.reduce, self.front, self.clip = n_sectors, reduce, float(front), clip
        self.limits = None if limits is None else _checked_limits(limits)
        self._known: list[_Sectors] = []

    def __call__(self, sweep: Sweep) -> np.ndarray:
        geometry = self._geometry(sweep.angles)
        if self._centred(geometry, sweep.origins):
            return self._reduce(geometry, sweep.ranges, geometry.index)
        return self._offset(geometry, sweep)

    def stack(self, sweeps) -> np.ndarray:
        """The rings of ``sweeps``, one a row: each the ring the maker gives it alone, those of a centred sensor
        of the same geometry reduced together (one array operation for all of them)."""
        out = np.empty((len(sweeps), self.n_sectors))
        centred: dict[int, tuple[_Sectors, list[int]]] = {}
        angles = origins = geometry = None
        for q, sweep in enumerate(sweeps):
            if sweep.angles is not angles:   # a reader's sweeps share their geometry's arrays
                angles, origins, geometry = sweep.angles, None, self._geometry(sweep.angles)
            if sweep.origins is not origins:
                origins, at_centre = sweep.origins, self._centred(geometry, sweep.origins)
            if at_centre:
                centred.setdefault(id(geometry), (geometry, []))[1].append(q)
            else:
                out[q] = self._offset(geometry, sweep)
        for geometry, at in centred.values():
            ranges = np.stack([np.asarray(sweeps[q].ranges, dtype=np.float64) for q in at])
            out[at] = self._reduce(geometry, ranges, geometry.index)
        return out

    @staticmethod
    def _centred(geometry: "_Sectors", origins) -> bool:
        """Whether the beams start at the base frame's origin (each bearing its beam's direction)."""
        if geometry.known(origins) is not None:   # a reader's shared origins, met before off the centre
            return False
        if origins is geometry.zero or not np.count_nonzero(origins):
            if not getattr(origins, "flags", origins).writeable:   # a reader's shared, read-only origins:
                geometry.zero = origins                              # the next sweep's need no test
            return True
        return False

    def _offset(self, geometry: "_Sectors", sweep: Sweep) -> np.ndarray:
        """The ring of a sweep whose beams start off the base frame's origin (module docstring)."""
        offsets = geometry.offsets(sweep.origins, self.front)
        r = np.asarray(sweep.ranges, dtype=np.float64)
        if self.reduce == "min":
            # deferred: numba's import and the kernel's first compilation, paid only for an offset sensor
            from ._sweep_kernels import offset_nearest

            ring = np.empty(self.n_sectors)
            offset_nearest(r, offsets.origins, geometry.cos, geometry.sin, geometry.index, offsets.safe,
                           geometry.bounds, *geometry.limits, self.n_sectors, self.front, ring)
            return ring if self.clip is None else np.minimum(ring, self.clip)
        with np.errstate(invalid="ignore"):
            distance = np.sqrt(np.maximum(r * (r + 2 * offsets.along) + offsets.squared, 0.0))
            moved = np.flatnonzero(r < offsets.safe)   # NaN and +inf: never moved (they keep their direction)
        if not moved.size:
            return self._reduce(geometry, distance, geometry.index)
        o = offsets.origins[moved]
        rm = r[moved]
        bearing = np.arctan2(o[:, 1] + rm * geometry.sin[moved], o[:, 0] + rm * geometry.cos[moved])
        low, high = geometry.limits
        now = _sectors_within(low + np.mod(bearing - self.front - low, 2 * math.pi), low, high, self.n_sectors)
        index = geometry.index.copy()
        index[moved] = now
        return reduce_sectors(distance, index, self.n_sectors, self.reduce, self.clip)

    def _reduce(self, geometry: "_Sectors", ranges, index) -> np.ndarray:
        if self.reduce == "min":
            return geometry.nearest(ranges, self.clip)
        return reduce_sectors(ranges, index, self.n_sectors, self.reduce, self.clip)

    def _geometry(self, angles) -> _Sectors:
        """The sectors of ``angles`` by direction (cached)."""
        for known in self._known:
            if known.angles is angles or (known.angles.shape == np.shape(angles)
                                          and np.array_equal(known.angles, angles)):
                return known
        sectors = _Sectors(np.asarray(angles, dtype=np.float64), self.n_sectors, self.limits, self.front)
        self._known = [sectors] + self._known[:3]   # a few sensors' geometries
        return sectors


class _Sectors:
    """A geometry's beams by sector: their index, and their order for reducing a sector at a time."""

    def __init__(self, angles: np.ndarray, n_sectors: int, limits, front: float):
        self.angles, self.zero, self.n_sectors = angles, None, n_sectors
        self._offsets: list[_Offsets] = []
        self._margin = self.cos = self.sin = self.bounds = None   # once a sweep of this geometry has offset origins
        # raises where the beams cannot fill the sectors
        self.index = sector_index(angles, n_sectors, limits, front)
        self.limits = limits if limits is not None else scan_limits(angles, front)
        inside = np.flatnonzero(self.index >= 0)
        self.order = inside[np.argsort(self.index[inside], kind="stable")]
        if np.array_equal(self.order, np.arange(len(angles))):
            self.order = None   # the beams are in sector order already (a single scan): no gathering
        self.starts = np.searchsorted(self.index[inside][np.argsort(self.index[inside], kind="stable")],
                                      np.arange(n_sectors))

    def known(self, origins) -> "_Offsets | None":
        """What :meth:`offsets` kept for these very ``origins``, if it did."""
        for known in self._offsets:
            if known.given is origins:
                return known
        return None

    def offsets(self, origins, front: float) -> "_Offsets":
        """What beams of this geometry from ``origins`` (off the centre) need (kept for the last few origins)."""
        known = self.known(origins)
        if known is not None:
            return known
        if self.cos is None:
            self.cos, self.sin = np.cos(self.angles), np.sin(self.angles)
            self._margin = self._margins(front)
            low, high = self.limits
            edges = front + low + (high - low) / self.n_sectors * np.arange(self.n_sectors + 1)
            self.bounds = np.column_stack([np.cos(edges), np.sin(edges)])   # each sector's first direction
        made = _Offsets(origins, self)
        if not getattr(origins, "flags", origins).writeable:   # read-only: kept, and known again by identity
            self._offsets = [made] + self._offsets[:3]
        return made

    def _margins(self, front: float) -> np.ndarray:
        """Each beam's direction's angle to its nearest sector boundary (0 beyond the limits), at most pi/2."""
        low, high = self.limits
        width = (high - low) / self.n_sectors
        a = low + np.mod(self.angles - front - low, 2 * math.pi)
        frac = (a - low) / width
        margin = np.minimum(frac - np.floor(frac), np.ceil(frac) - frac) * width
        margin = np.where(self.index >= 0, margin - 1e-9, 0.0)   # a lower bound, whatever the roundings
        return np.clip(margin, 0.0, math.pi / 2)

    def nearest(self, ranges: np.ndarray, clip: float | None) -> np.ndarray:
        """Each sector's nearest valid range (``+inf`` where none): ``reduce_sectors(..., "min")``'s values, of
        one sweep's ranges or of several (a row each)."""
        r = ranges if self.order is None else ranges[..., self.order]
        ring = np.fmin.reduceat(r, self.starts, axis=-1)   # fmin passes NaN (no information) over
        ring[np.isnan(ring)] = np.inf
        return ring if clip is None else np.minimum(ring, clip)


class _Offsets:
    """For beams from ``origins``: ``o.u``, ``|o|^2``, and the range beyond which a beam keeps its sector."""

    def __init__(self, given, sectors: _Sectors):
        self.given = given
        self.origins = o = np.asarray(given, dtype=np.float64)
        self.along = o[:, 0] * sectors.cos + o[:, 1] * sectors.sin
        self.squared = o[:, 0] ** 2 + o[:, 1] ** 2
        norm = np.sqrt(self.squared)
        with np.errstate(divide="ignore", invalid="ignore"):
            # asin(|o| / (r - |o|)) < margin  <=>  r > |o| + |o| / sin(margin); margin 0: never safe
            self.safe = np.where(norm > 0, norm + norm / np.sin(sectors._margin), 0.0) * (1 + 1e-9)


def sweep_ring(sweep: Sweep, n_sectors: int = 16, reduce="min", limits=None, front: float = 0.0,
               clip: float | None = None) -> np.ndarray:
    """A sweep as a ring of ``n_sectors`` ranges seen from the base frame's origin (see the module docstring).

    Examples
    --------
    >>> zero = np.zeros((3, 2))
    >>> centred = Sweep(0.0, zero, np.deg2rad([-60.0, 0.0, 60.0]), np.array([2.0, 1.0, np.inf]), None)
    >>> sweep_ring(centred, 3).tolist()
    [2.0, 1.0, inf]
    >>> ahead = Sweep(0.0, zero + [0.5, 0.0], centred.angles, centred.ranges, None)
    >>> sweep_ring(ahead, 3).round(3).tolist()   # the laser 0.5 m ahead: what it sees 1 m ahead is 1.5 m away
    [2.291, 1.5, inf]
    """
    return RingMaker(n_sectors, reduce, limits, front, clip)(sweep)


def laser_ring(scan: LaserScan, n_sectors: int, reduce="min", limits=None, front: float = 0.0,
               clip: float | None = None) -> np.ndarray:
    """A laser scan (its angles the robot's) as a ring of ``n_sectors`` ranges: cleaned, cut into sectors, reduced.

    Examples
    --------
    >>> scan = LaserScan(0.0, np.array([1.0, np.nan, 2.0, -np.inf]), angle_min=-np.pi / 2,
    ...                  angle_increment=np.pi / 3, range_min=0.25)
    >>> laser_ring(scan, 2).tolist()
    [1.0, 0.25]
    """
    index = sector_index(scan.angles, n_sectors, limits, front)
    ranges = clean_ranges(scan.ranges, scan.range_min, scan.range_max)
    return reduce_sectors(ranges, index, n_sectors, reduce, clip)


def reference_ring(sweep: Sweep, n_sectors: int = 16, reduce="min", limits=None, front: float = 0.0,
                   clip: float | None = None) -> np.ndarray:
    """The ring of every beam's end point, each bearing computed: the readable specification of :class:`RingMaker`."""
    angles = np.asarray(sweep.angles, dtype=np.float64)
    index = sector_index(angles, n_sectors, None if limits is None else _checked_limits(limits), front)
    low, high = _checked_limits(limits) if limits is not None else scan_limits(angles, front)
    ranges = np.asarray(sweep.ranges, dtype=np.float64)
    o = np.asarray(sweep.origins, dtype=np.float64)
    if np.any(o):
        hit = np.isfinite(ranges)
        r = np.where(hit, ranges, 0.0)
        x, y = o[:, 0] + r * np.cos(angles), o[:, 1] + r * np.sin(angles)
        bearings = np.where(hit, np.arctan2(y, x), angles)
        ranges = np.where(hit, np.sqrt(x * x + y * y), ranges)
        index = _sectors_within(low + np.mod(bearings - front - low, 2 * math.pi), low, high, n_sectors)
    return reduce_sectors(ranges, index, n_sectors, reduce, clip)
