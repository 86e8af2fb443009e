"""The ``points`` input: a scan as the robot's pose, the paper's ring and each sector's end point in the world.

A memory that knows *where* something was seen needs the robot's pose and
where each echo lies in the world; the paper's ring alone is what the robot
sees from its own centre, wherever it stands. The ``points`` input carries
both, one row a scan, ``3 + 3 n`` columns for a ring of ``n`` sectors::

    x, y, heading                  the robot's pose in the world frame (m, m, rad; REP 103/105)
    near_0 ... near_{n-1}          the paper's ring: 1 - min(r_k, T) / T (Marsland et al. 2000, 4.1)
    x_0 ... x_{n-1}                each sector's end point in the world frame (m)
    y_0 ... y_{n-1}

A sector's end point is where its nearest echo lies; a sector with no echo
within the threshold ``T`` (``near`` = 0) has its end point ``T`` along its
direction, as far as its beams saw free space. The ring's columns are the
ring input itself, so a detector of rings reads the same ring here, with the
pose and the points beside it. The layout is ours; it holds any sensor whose
rays start near the robot's centre (a laser's mount, a sonar ring's radius).
It lives with the scans, beside the ring, because it is what a scan becomes;
the detectors that read it (:mod:`novelty.maps`) and the benchmark that
checks a task's rows against it import it from here.

Where the rows come from:

- a recording's sweeps (:func:`sweep_points`; :class:`~novelty.io.ros.messages.Sweep`:
  beams in the base frame, mounts included, and the robot's pose). The
  ring is :class:`~novelty.io.scans.sweep_rings.RingMaker`'s with the
  nearest echo, preprocessed as the paper does (``1 - min(r, T) / T``), the
  same values as the ring input gives; each sector's end point is that of
  the sector's nearest beam (the sectors cut by the beams' directions,
  :func:`novelty.io.scans.sectors.sector_index`; the ring's own where the
  sensor sits at the base frame's origin, as in the Radish logs), moved
  into the world frame by the pose; a sector whose nearest echo lies
  beyond ``T`` (or that has none) ends ``T`` from the robot's centre along
  the direction of that beam (of its middle beam if none returned);
- a ring of sensors at known bearings (:func:`ring_points`: the simulated
  sonar ring).

:func:`split_points` reads rows back and refuses any that do not have the layout.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ...sonar.preprocessing import preprocess
from .sectors import sector_index
from .sweep_rings import RingMaker

__all__ = ["POSE_COLUMNS", "POINTS_SECTORS", "MAX_COORDINATE", "PointsMaker", "points_columns", "split_points",
           "check_points", "ring_points", "sweep_points", "reference_points", "example_rows"]

#: The pose's columns, first in every row.
POSE_COLUMNS = ("x", "y", "heading")
#: A recording's sectors of the points input unless given: the habituating maps were measured on lasers with
#: 180 (benchmarks/suites/maps-exploration.toml); a sensor of fewer beams gets one sector a beam
POINTS_SECTORS = 180

#: Coordinates (m) beyond which a grid of the world refuses a row: its cells' indices stay exact.
MAX_COORDINATE = 1e6


def points_columns(n_sectors: int) -> list[str]:
    """The names of the ``3 + 3 n`` columns.

    >>> points_columns(2)
    ['x', 'y', 'heading', 'near_0', 'near_1', 'x_0', 'x_1', 'y_0', 'y_1']
    """
    return [*POSE_COLUMNS, *(f"{part}_{k}" for part in ("near", "x", "y") for k in range(n_sectors))]


def check_points(X, who: str = "This detector") -> int:
    """The number of sectors of rows ``X`` in the ``points`` layout; a ValueError naming it otherwise."""
    X = np.asarray(X)
    d = X.shape[-1] if X.ndim else 0
    if X.ndim != 2 or d < 6 or (d - len(POSE_COLUMNS)) % 3:
        raise ValueError(
            f"{who} reads rows of the 'points' input: the robot's pose (x, y, heading), n nearness values "
            f"in [0, 1], then the n end points' x and y in the world frame (3 + 3n columns, n >= 1); got "
            f"{d} columns. Give the task inputs='points' (a recording's or a simulated task's option; "
            "novelty.io.scans.points).")
    n = (d - len(POSE_COLUMNS)) // 3
    near = X[:, 3:3 + n]
    if np.any(near < 0) or np.any(near > 1):
        raise ValueError(f"{who} reads rows of the 'points' input, whose columns 3 to {2 + n} are the ring's "
                         f"nearness in [0, 1]; got values from {near.min():.4g} to {near.max():.4g}. Are these "
                         "rows a ring without the pose?")
    return n


def split_points(X, who: str = "This detector", bounded: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows of the ``points`` layout as (poses (m, 3), nearness (m, n), end points (m, n, 2)).

    ``bounded``: refuse a pose or end point farther than :data:`MAX_COORDINATE` from the origin (a grid of
    the world indexes its cells by them).

    >>> poses, near, ends = split_points([[0.0, 0.0, 0.0, 0.5, 0.0, 2.0, 4.0, 0.0, 0.0]])
    >>> near.tolist(), ends.tolist()
    ([[0.5, 0.0]], [[[2.0, 0.0], [4.0, 0.0]]])
    """
    X = np.asarray(X, dtype=np.float64)
    n = check_points(X, who)
    poses, ends = X[:, :3], np.stack([X[:, 3 + n:3 + 2 * n], X[:, 3 + 2 * n:]], axis=-1)
    if bounded and (np.abs(poses[:, :2]).max() > MAX_COORDINATE or np.abs(ends).max() > MAX_COORDINATE):
        raise ValueError(f"{who}: a pose or end point lies more than {MAX_COORDINATE:g} m from the world's origin; "
                         "give poses in metres in a local frame (odom or map).")
    return poses, X[:, 3:3 + n], ends


def ring_points(X, poses, bearings, threshold: float, offset: float = 0.0) -> np.ndarray:
    """Rings of sensors at fixed ``bearings`` as ``points`` rows.

    Sensor ``k`` points ``bearings[k]`` (rad, counter-clockwise from the
    robot's front) and sits ``offset`` m from the robot's centre on that
    axis (a sonar ring's radius); its reading ``near`` in the paper's
    encoding is a range ``r = T (1 - near)`` from the sensor, so its end
    point lies ``offset + r`` from the centre along the axis (``offset + T``
    where ``near`` = 0: no echo, free that far).

    Parameters
    ----------
    X : array-like of shape (m, n)
        The rings, each value ``1 - min(r, T) / T``.
    poses : array-like of shape (m, 3)
        The robot's pose at each ring (x, y, heading).
    bearings : array-like of shape (n,)
    threshold : float
        ``T`` (m).
    offset : float, default=0.0

    Examples
    --------
    >>> row = ring_points([[0.5, 0.0]], [[1.0, 0.0, np.pi / 2]], [0.0, np.pi], 4.0, offset=0.2)
    >>> row.round(3).tolist()   # ahead (north) 2.2 m, behind (south) 4.2 m
    [[1.0, 0.0, 1.571, 0.5, 0.0, 1.0, 1.0, 2.2, -4.2]]
    """
    X = np.asarray(X, dtype=np.float64)
    poses = np.asarray(poses, dtype=np.float64)
    bearings = np.asarray(bearings, dtype=np.float64).reshape(-1)
    if X.ndim != 2 or X.shape[1] != bearings.size or poses.shape != (X.shape[0], 3):
        raise ValueError(f"Expected rings (m, n), poses (m, 3) and n bearings; got {X.shape}, {poses.shape} and "
                         f"{bearings.size} bearings.")
    if not threshold > 0 or not offset >= 0:
        raise ValueError(f"threshold must be positive and offset >= 0 (m); got {threshold!r} and {offset!r}.")
    reach = offset + threshold * (1.0 - np.clip(X, 0.0, 1.0))
    axis = poses[:, 2:3] + bearings[None, :]
    ex = poses[:, 0:1] + reach * np.cos(axis)
    ey = poses[:, 1:2] + reach * np.sin(axis)
    heading = (poses[:, 2:3] + np.pi) % (2 * np.pi) - np.pi
    return np.hstack([poses[:, :2], heading, X, ex, ey])



def sweep_points(sweeps: Sequence, sectors: int = 16, threshold: float = 4.0) -> np.ndarray:
    """Each sweep (with its pose) as a ``points`` row of ``3 + 3 sectors`` columns (module docstring).

    Examples
    --------
    >>> from novelty.io.scans.sweeps import Sweep
    >>> ahead = Sweep(0.0, np.zeros((4, 2)), np.deg2rad([-67.5, -22.5, 22.5, 67.5]),
    ...               np.array([1.0, 2.0, np.inf, 3.0]), np.array([10.0, 5.0, np.pi / 2]))
    >>> sweep_points([ahead], sectors=2).round(3).tolist()   # facing +y: 1 m to its right, 3 m ahead-left
    [[10.0, 5.0, 1.571, 0.75, 0.25, 10.924, 7.228, 5.383, 6.148]]
    """
    return PointsMaker(sectors, threshold).rows(sweeps)


#: Sweeps made into rows together (:meth:`PointsMaker.rows`): a block's ranges stay about a MB at 1,080 beams
BLOCK = 128


class PointsMaker:
    """:func:`sweep_points` with its sectors and threshold fixed, keeping each geometry's sectors.

    The beams' sectors depend on their directions alone: for a geometry (the
    same ``angles`` array, or equal ones) they are worked out once, with each
    sector's beams in order and its middle beam, and the ring's
    (:class:`~novelty.io.scans.sweep_rings.RingMaker`) kept too. Each sector's
    end point is its nearest beam's (the first of the nearest, in the beams'
    order), as the module docstring says. :meth:`rows` makes many sweeps' rows
    at once, the sweeps of a geometry together (a recording's sweeps share a
    few geometries): their rings reduced in one array operation, their end
    points placed in the world by one compiled pass
    (:func:`novelty.io.scans._sweep_kernels.world_ends`), with the values of
    :func:`reference_points`, the numpy specification, bit for bit.
    """

    def __init__(self, sectors: int = 16, threshold: float = 4.0):
        if isinstance(sectors, bool) or not isinstance(sectors, (int, np.integer)) or sectors < 1:
            raise ValueError(f"The points input needs one number of sectors (an int >= 1); got {sectors!r}.")
        self.sectors, self.threshold = int(sectors), float(threshold)
        self.rings = RingMaker(self.sectors, "min")
        self._known: list[_Beams] = []
        self.world_ends = None   # compiled, imported at the first rows

    def __call__(self, sweep) -> np.ndarray:
        """The sweep's ``points`` row (``3 + 3 sectors`` values)."""
        return self.rows([sweep])[0]

    def rows(self, sweeps: Sequence) -> np.ndarray:
        """The ``points`` rows of ``sweeps``, one a sweep, in their order: shape (len(sweeps), 3 + 3 sectors)."""
        sweeps = list(sweeps)
        out = np.empty((len(sweeps), 3 + 3 * self.sectors))
        for start in range(0, len(sweeps), BLOCK):
            block = sweeps[start:start + BLOCK]
            for beams, at in self._by_geometry(block).values():
                out[start + np.asarray(at)] = self._rows(beams, [block[q] for q in at])
        return out

    def _by_geometry(self, sweeps: list) -> dict:
        """The sweeps' places grouped by geometry, each sweep checked in order (a pose, sectors its beams fill)."""
        groups: dict[int, tuple[_Beams, list[int]]] = {}
        angles = at = None
        for q, sweep in enumerate(sweeps):
            if sweep.pose is None:
                raise ValueError(f"The sweep at t={sweep.time} has no pose: the points input places each echo in "
                                 "the world frame (give the recording's poses, pose_topic=).")
            if sweep.angles is not angles:   # a reader's sweeps share their geometry's arrays
                angles = sweep.angles
                beams = self._geometry(angles)
                at = groups.setdefault(id(beams), (beams, []))[1]
            at.append(q)
        return groups

    def _rows(self, beams: "_Beams", sweeps: list) -> np.ndarray:
        """The rows of sweeps of one geometry."""
        n = self.sectors
        out = np.empty((len(sweeps), 3 + 3 * n))
        out[:, 3:3 + n] = preprocess(self.rings.stack(sweeps), self.threshold)
        out[:, :2] = [sweep.pose[:2] for sweep in sweeps]
        yaw = np.array([sweep.pose[2] for sweep in sweeps], dtype=np.float64).tolist()
        out[:, 2] = [(a + math.pi) % (2 * math.pi) - math.pi for a in yaw]
        # the rotation by the C library's cosine and sine, as one sweep's row has it
        pose = np.c_[out[:, :2], [math.cos(a) for a in yaw], [math.sin(a) for a in yaw]]
        if self.world_ends is None:
            # deferred: numba's import and the kernel's first compilation, paid where points rows are made
            from ._sweep_kernels import world_ends

            self.world_ends = world_ends
        ranges = np.stack([np.asarray(sweep.ranges, dtype=np.float64) for sweep in sweeps])
        self.world_ends(ranges, _origins(sweeps), beams.unit, beams.order, beams.starts, beams.middle,
                        self.threshold, pose, out[:, 3 + n:3 + 2 * n], out[:, 3 + 2 * n:])
        return out

    def _geometry(self, angles) -> "_Beams":
        for known in self._known:
            if known.angles is angles or (known.angles.shape == np.shape(angles)
                                          and np.array_equal(known.angles, angles)):
                return known
        beams = _Beams(np.asarray(angles, dtype=np.float64), self.sectors)
        self._known = [beams] + self._known[:3]   # a few sensors' geometries
        return beams


def _origins(sweeps: list) -> np.ndarray:
    """The sweeps' beams' origins, (1, beams, 2) where they share one array, else (m, beams, 2)."""
    shared = all(sweep.origins is sweeps[0].origins for sweep in sweeps)
    return np.stack([np.asarray(sweep.origins, dtype=np.float64).reshape(-1, 2)
                     for sweep in (sweeps[:1] if shared else sweeps)])


def reference_points(sweeps: Sequence, sectors: int = 16, threshold: float = 4.0) -> np.ndarray:
    """The rows of :func:`sweep_points` in numpy, one sweep at a time: the readable specification of the
    compiled :meth:`PointsMaker.rows`, which gives the same values bit for bit (tested)."""
    rings = RingMaker(int(sectors), "min")
    rows = []
    for sweep in sweeps:
        if sweep.pose is None:
            raise ValueError(f"The sweep at t={sweep.time} has no pose.")
        near = preprocess(rings(sweep), threshold)
        beams = _Beams(np.asarray(sweep.angles, dtype=np.float64), int(sectors))
        origins = np.asarray(sweep.origins, dtype=np.float64).reshape(-1, 2)
        ends = beams.ends(np.asarray(sweep.ranges, dtype=np.float64), origins, threshold)
        x, y, yaw = (float(v) for v in sweep.pose)
        c, s = math.cos(yaw), math.sin(yaw)
        world_x = x + c * ends[:, 0] - s * ends[:, 1]
        world_y = y + s * ends[:, 0] + c * ends[:, 1]
        rows.append(np.r_[x, y, (yaw + math.pi) % (2 * math.pi) - math.pi, near, world_x, world_y])
    return np.array(rows, dtype=np.float64).reshape(-1, 3 + 3 * int(sectors))


class _Beams:
    """A geometry's beams by sector: their directions, the beams of each sector in order, and its middle beam."""

    def __init__(self, angles: np.ndarray, sectors: int):
        self.angles = angles
        self.unit = np.c_[np.cos(angles), np.sin(angles)]
        index = sector_index(angles, sectors)   # raises where the beams cannot fill the sectors
        inside = np.flatnonzero(index >= 0)
        self.order = inside[np.argsort(index[inside], kind="stable")]   # each sector's beams, in the beams' order
        self.sector = index[self.order]
        counts = np.bincount(self.sector, minlength=sectors)
        self.starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        self.middle = self.order[self.starts + counts // 2]

    def ends(self, ranges: np.ndarray, origins: np.ndarray, threshold: float) -> np.ndarray:
        """Each sector's end point in the base frame, of one sweep's ``ranges`` from its beams' ``origins``: its
        nearest beam's echo, or ``threshold`` along it."""
        echo = np.isfinite(ranges)
        ends = origins + np.where(echo, ranges, 0.0)[:, None] * self.unit
        distance = np.where(echo, np.hypot(ends[:, 0], ends[:, 1]), np.inf)
        # the first beam of each sector at the sector's least distance; the middle beam where none returned
        d = distance[self.order]
        least = np.minimum.reduceat(d, self.starts)
        at = np.flatnonzero(d == least[self.sector])
        first = at[np.unique(self.sector[at], return_index=True)[1]]
        j = np.where(np.isfinite(least), self.order[first], self.middle)
        within = distance[j] <= threshold
        direction = np.where(echo[j][:, None], ends[j], self.unit[j])
        with np.errstate(divide="ignore", invalid="ignore"):   # an echo at the centre is within: not used
            beyond = threshold * direction / np.hypot(direction[:, 0], direction[:, 1])[:, None]
        return np.where(within[:, None], ends[j], beyond)


def example_rows(seed: int = 0, n: int = 120) -> np.ndarray:
    """Rows of the points input for generic checks: a robot driving along a corridor 4 m wide.

    Eight sectors all round; the walls at y = +-2 m, the robot's lateral
    position and heading wandering by a seeded random walk, no echo beyond 4 m.

    >>> example_rows(n=5).shape
    (5, 27)
    """
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 0.1 * n, n)
    y = np.clip(np.cumsum(rng.normal(scale=0.05, size=n)), -1.0, 1.0)
    heading = np.clip(np.cumsum(rng.normal(scale=0.05, size=n)), -0.5, 0.5)
    bearings = heading[:, None] + np.arange(8) * (np.pi / 4)
    s = np.sin(bearings)
    with np.errstate(divide="ignore"):
        r = np.where(s > 0, (2.0 - y[:, None]) / s, np.where(s < 0, (-2.0 - y[:, None]) / s, np.inf))
    r = np.minimum(r, 4.0)
    return np.c_[x, y, heading, 1.0 - r / 4.0, x[:, None] + r * np.cos(bearings), y[:, None] + r * s]
