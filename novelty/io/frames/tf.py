"""A small transform tree of our own, as tf2 keeps one: static and moving frames, chained lookups at a time.

Each frame has one parent (REP 105's tree: ``map -> odom -> base_footprint
-> base_link -> laser``); each edge holds the child's pose in its parent,
static (``/tf_static``: true at every time) or a time series (``/tf``, an
odometry topic). :meth:`TfBuffer.lookup` walks both frames up to their
common ancestor and composes the edges at the time asked:

- a moving edge is interpolated between the samples on either side of the
  time (translations linearly, rotations by slerp), as tf2 does;
- outside its samples an edge is held at its first or last value within
  ``tolerance`` seconds, and otherwise refused (tf2 refuses any
  extrapolation; a recording's streams start and stop a few milliseconds
  apart, so a small hold keeps the last scans);
- samples older than ``cache`` seconds before an edge's newest are
  forgotten (tf2's default cache is 10 s; here in batches, once they are
  twice that old), and samples closer in time than :attr:`TfBuffer.resolution`
  thinned, so that an edge holds at most about
  :data:`~novelty.io.ros.caps.MAX_TF_SAMPLES`;
- a transform that names one frame twice, places nothing (a zero or
  non-finite quaternion, a non-finite translation), closes a loop, or makes
  a chain deeper than :data:`~novelty.io.ros.caps.MAX_TF_DEPTH` frames or a tree
  of more than :data:`~novelty.io.ros.caps.MAX_TF_FRAMES` is refused, and a
  reader skips it and counts it, as tf2 does.

A lookup that fails raises :class:`TfError`, which names the frames, the
chains found from each to its root, and the times held.

References
----------
Foote, T. (2013). tf: The transform library. IEEE TePRA (tf2's design:
one parent a frame, time-stamped edges, interpolation at lookup).
REP 105, "Coordinate Frames for Mobile Platforms".
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field

from ..ros import caps
from ..ros.messages import Transform
from ..ros.quaternions import IDENTITY, conjugate, multiply, normalized, rotate, slerp

__all__ = ["TfBuffer", "TfError", "Placement"]


class TfError(ValueError):
    """A transform that the tree cannot give: a frame it lacks, frames in two trees, or a time it does not cover."""


@dataclass(frozen=True)
class Placement:
    """A rigid transform: a point ``p`` of the child frame is ``rotate(rotation, p) + translation`` in the parent."""

    translation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[float, float, float, float] = IDENTITY

    def then(self, inner: "Placement") -> "Placement":
        """This placement after ``inner``: a point of ``inner``'s child frame in this one's parent."""
        mx, my, mz = rotate(self.rotation, inner.translation)
        tx, ty, tz = self.translation
        return Placement((mx + tx, my + ty, mz + tz), multiply(self.rotation, inner.rotation))

    def inverse(self) -> "Placement":
        back = conjugate(self.rotation)
        return Placement(tuple(-c for c in rotate(back, self.translation)), back)

    @property
    def planar(self) -> tuple[float, float, float]:
        """(x, y, yaw): the placement seen from above (REP 103's heading about z)."""
        x, y, z, w = self.rotation
        return self.translation[0], self.translation[1], math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


@dataclass
class _Edge:
    parent: str
    static: bool
    times: list[float] = field(default_factory=list)
    values: list[Placement] = field(default_factory=list)


class TfBuffer:
    """The frames of a recording's ``tf`` messages, looked up at a time (see the module docstring).

    Parameters
    ----------
    tolerance : float, default=0.2
        Seconds beyond a moving edge's first or last sample at which it is held.
    cache : float, default=10.0
        Seconds of a moving edge's history kept before its newest sample.
    """

    def __init__(self, tolerance: float = 0.2, cache: float = 10.0):
        self.tolerance, self.cache = float(tolerance), float(cache)
        self._edges: dict[str, _Edge] = {}
        self._children: dict[str, set[str]] = {}   # each parent's children
        self._paths: dict[tuple[str, str], tuple[list[str], list[str]]] = {}   # until the tree's shape changes
        self._chains: dict[str, list[str]] = {}   # likewise
        self._named: set[str] = set()   # every frame an edge named: at most MAX_TF_FRAMES

    @property
    def resolution(self) -> float:
        """Seconds within which a moving edge's samples are thinned: ``4 * cache / MAX_TF_SAMPLES``."""
        return 4 * self.cache / caps.MAX_TF_SAMPLES

    # -------------------------------------------------------------- adding
    def add(self, transform: Transform) -> None:
        """Add one transform (``static`` ones replace the edge; moving ones join its series in time order).

        Refused (:class:`TfError`, saying why; tf2 skips such a transform
        with a warning): two frames that are not two, a placement that is
        not finite or not a rotation, an edge that would make a loop, a
        chain of more than :data:`~novelty.io.ros.caps.MAX_TF_DEPTH` frames or a
        tree of more than :data:`~novelty.io.ros.caps.MAX_TF_FRAMES`.
        """
        child, parent = transform.child, transform.parent
        if not child or not parent or child == parent:
            raise TfError(f"A transform needs two different frames; got {parent!r} -> {child!r}.")
        value = Placement(_translation(transform), _rotation(transform))
        edge = self._edges.get(child)
        if edge is None or edge.parent != parent or edge.static != transform.static:
            # a frame moved to another parent (or between /tf and /tf_static): the newest word wins, as in tf2
            if edge is None or edge.parent != parent:
                self._check_shape(transform)
                if edge is not None:
                    self._children[edge.parent].discard(child)
                self._children.setdefault(parent, set()).add(child)
            edge = self._edges[child] = _Edge(parent, transform.static)
            self._paths.clear()
            self._chains.clear()
        if transform.static:
            edge.times, edge.values = [transform.stamp], [value]
            return
        _join(edge, transform.stamp, value, self.resolution)
        times = edge.times
        if times[0] < times[-1] - 2 * self.cache:   # forgotten in batches: a sample's deletion is O(samples)
            old = bisect.bisect_left(times, times[-1] - self.cache)
            # keep one sample before the window, for interpolating into it
            del times[:old - 1], edge.values[:old - 1]

    def _check_shape(self, transform: Transform) -> None:
        """Refuse a new edge that would make a loop, too deep a chain or too many frames."""
        child, parent = transform.child, transform.parent
        where = f"{parent} -> {child} at {transform.stamp:.3f} s"
        up = [parent]
        while up[-1] in self._edges and len(up) <= caps.MAX_TF_DEPTH:
            up.append(self._edges[up[-1]].parent)
            if up[-1] == child:
                raise TfError(f"{where}: makes a loop ({' -> '.join(reversed(up))} -> {child}).")
        depth = len(up) + _height(self._children, child, caps.MAX_TF_DEPTH)
        if depth > caps.MAX_TF_DEPTH:
            raise TfError(f"{where}: makes a chain of {depth} frames; at most {caps.MAX_TF_DEPTH} are read "
                          f"(novelty.io.ros.caps.MAX_TF_DEPTH).")
        if len(self._named | {child, parent}) > caps.MAX_TF_FRAMES:
            raise TfError(f"{where}: the tree would name {len(self._named) + 1:,} frames; at most "
                          f"{caps.MAX_TF_FRAMES:,} are read (novelty.io.ros.caps.MAX_TF_FRAMES).")
        self._named.update((child, parent))

    def add_all(self, transforms) -> None:
        for t in transforms:
            self.add(t)

    # -------------------------------------------------------------- the tree
    @property
    def frames(self) -> list[str]:
        """Every frame named, parents and children."""
        return sorted(set(self._edges) | {p for p, children in self._children.items() if children})

    def chain(self, frame: str) -> list[str]:
        """``frame`` and its ancestors up to its root: ``[frame, parent, ..., root]`` (a new list)."""
        known = self._chains.get(frame)
        if known is None:
            known = [frame]
            while known[-1] in self._edges:   # no loops: refused as they are added
                known.append(self._edges[known[-1]].parent)
            self._chains[frame] = known
        return list(known)

    def root(self, frame: str) -> str:
        return self.chain(frame)[-1]

    def parent(self, frame: str) -> str | None:
        edge = self._edges.get(frame)
        return None if edge is None else edge.parent

    def has(self, frame: str) -> bool:
        return frame in self._edges or bool(self._children.get(frame))

    def is_static(self, target: str, source: str) -> bool:
        """Whether every edge between the two frames is static (the lookup then holds at all times)."""
        up, down = self._path(target, source)
        return all(self._edges[f].static for f in up + down)

    def newest(self, target: str, source: str) -> float:
        """The time up to which every moving edge between the frames has samples (``inf`` if none moves)."""
        up, down = self._path(target, source)
        return min((self._edges[f].times[-1] for f in up + down if not self._edges[f].static), default=math.inf)

    def describe(self) -> str:
        """The tree as its chains from each leaf to its root: ``odom -> base_footprint -> base_link; ...``."""
        children = set(self._edges)
        parents = {e.parent for e in self._edges.values()}
        leaves = sorted(children - parents)
        return "; ".join(" -> ".join(reversed(self.chain(leaf))) for leaf in leaves) or "no transforms"

    # -------------------------------------------------------------- lookups
    def lookup(self, target: str, source: str, time: float) -> Placement:
        """``source``'s placement in ``target`` at ``time``: a point of ``source`` as ``target`` sees it."""
        up, down = self._path(target, source)
        placement = Placement()
        for frame in reversed(up):      # source's ancestors below the common one, outermost first
            placement = placement.then(self._at(frame, time))
        inner = Placement()
        for frame in reversed(down):
            inner = inner.then(self._at(frame, time))
        return inner.inverse().then(placement)

    def _path(self, target: str, source: str) -> tuple[list[str], list[str]]:
        """The frames whose edges lead from ``source`` and from ``target`` up to their common ancestor."""
        known = self._paths.get((target, source))
        if known is None:
            known = self._paths[(target, source)] = self._walk(target, source)
        return known

    def _walk(self, target: str, source: str) -> tuple[list[str], list[str]]:
        for frame, role in ((target, "target"), (source, "source")):
            if not self.has(frame):
                raise TfError(f"No transform names frame {frame!r} (the {role}); the tree: {self.describe()}.")
        up, down = self.chain(source), self.chain(target)
        if up[-1] != down[-1]:
            raise TfError(f"Frames {target!r} and {source!r} are in two trees: {' -> '.join(reversed(down))} "
                          f"and {' -> '.join(reversed(up))}; the tree: {self.describe()}.")
        common = next(f for f in up if f in down)
        return up[:up.index(common)], down[:down.index(common)]

    def _at(self, child: str, time: float) -> Placement:
        edge = self._edges[child]
        if edge.static:
            return edge.values[0]
        times = edge.times
        i = bisect.bisect_left(times, time)
        if i < len(times) and times[i] == time:
            return edge.values[i]
        if 0 < i < len(times):
            a, b = edge.values[i - 1], edge.values[i]
            f = (time - times[i - 1]) / (times[i] - times[i - 1])
            return Placement(tuple(p + f * (q - p) for p, q in zip(a.translation, b.translation)),
                             slerp(a.rotation, b.rotation, f))
        end = 0 if i == 0 else len(times) - 1
        if abs(time - times[end]) <= self.tolerance:
            return edge.values[end]
        side = "before its first" if i == 0 else "after its last"
        raise TfError(f"The transform {edge.parent} -> {child} is asked for at {time:.3f} s, "
                      f"{abs(time - times[end]):.3f} s {side} ({times[0]:.3f} to {times[-1]:.3f} s held, "
                      f"{self.tolerance} s tolerated).")


def _translation(transform: Transform) -> tuple[float, float, float]:
    t = tuple(float(v) for v in transform.translation)
    if not all(math.isfinite(v) for v in t):
        raise TfError(f"{transform.parent} -> {transform.child} at {transform.stamp:.3f} s: a translation that is "
                      f"not finite {t}.")
    return t


def _rotation(transform: Transform) -> tuple[float, float, float, float]:
    q = tuple(float(v) for v in transform.rotation)
    where = f"{transform.parent} -> {transform.child} at {transform.stamp:.3f} s"
    if not all(math.isfinite(v) for v in q):
        raise TfError(f"{where}: a rotation that is not finite {q}.")
    norm = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
    if norm < 1e-24:
        raise TfError(f"{where}: a zero quaternion {q}, which is no rotation.")
    return q if abs(norm - 1.0) <= 1e-9 else normalized(q)   # most arrive unit already


def _join(edge: _Edge, stamp: float, value: Placement, resolution: float) -> None:
    """A moving sample into its edge's series, in time order, thinned: of samples closer than
    ``resolution``, the newest replaces the one before it, and one between two is left out."""
    times = edge.times
    if not times or stamp >= times[-1]:   # in time order, as a recording mostly is
        if len(times) > 1 and stamp - times[-2] < resolution:
            times[-1], edge.values[-1] = stamp, value
        else:
            times.append(stamp)
            edge.values.append(value)
        return
    at = bisect.bisect_right(times, stamp)
    if (at and stamp - times[at - 1] < resolution) or times[at] - stamp < resolution:
        return
    times.insert(at, stamp)
    edge.values.insert(at, value)


def _height(children: dict[str, set[str]], frame: str, limit: int) -> int:
    """The frames of the longest chain from ``frame`` down through its descendants (at most ``limit + 1``)."""
    level, height = {frame}, 0
    while level and height <= limit:
        height += 1
        level = {c for f in level for c in children.get(f, ())}
    return height
