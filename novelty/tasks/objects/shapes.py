"""Virtual objects in a recording's world frame: boxes, cylinders and wall segments, each with its time.

Each object is a convex set in the plane of the recording's poses (the
world frame: ``odom`` or ``map``, REP 105), present from ``start`` to
``end`` (s, the recording's clock; present at ``start``, gone at ``end``).
Three questions are asked of it, all in closed form:

- :meth:`entry`: how far along each ray, from its origin, the ray first
  meets the object's surface (``inf`` where it misses, 0 where the origin
  is inside): a laser beam's range to it;
- :meth:`closest`: the point of the object nearest each given point (the
  point itself where it is inside): a sonar cone's nearest echo
  (:mod:`novelty.tasks.objects.raycast`) and the robot's clearance;
- :meth:`depth`: how far inside the object each point lies (negative
  outside): what the robot saw inside it.

A :class:`Wall` is a thin :class:`Box` along a segment, so there are two
geometries: the slab test for a box (Kay & Kajiya 1986; a ray meets a box
where it is within all of its slabs at once) and the quadratic of a circle.

References
----------
Kay, T. L. & Kajiya, J. T. (1986). Ray tracing complex scenes. SIGGRAPH '86,
269-278 (the slab intersection of a ray and a box).
REP 103 (units, counter-clockwise angles) and REP 105 (the world frames).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Box", "Cylinder", "Wall", "SHAPES"]


def _check(name: str, obj, lengths: dict) -> None:
    if not isinstance(obj.name, str) or not obj.name:
        raise ValueError(f"A {name} needs a name (a non-empty str); got {obj.name!r}.")
    for key, value in lengths.items():
        if not (isinstance(value, (int, float, np.floating, np.integer)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} {obj.name!r}: {key} must be a positive length (m); got {value!r}.")
    if not obj.start < obj.end or math.isnan(obj.start) or math.isnan(obj.end):
        raise ValueError(f"{name} {obj.name!r}: start ({obj.start!r}) must be before end ({obj.end!r}).")


def _points(points) -> np.ndarray:
    return np.asarray(points, dtype=np.float64).reshape(-1, 2)


class _Timed:
    """What every object shares: its name and the time it stands in the world."""

    def present(self, time) -> np.ndarray:
        """Whether the object stands in the world at each ``time`` (s): ``start <= time < end``."""
        t = np.asarray(time, dtype=np.float64)
        return (t >= self.start) & (t < self.end)


@dataclass(frozen=True)
class Box(_Timed):
    """A box of ``length`` (along its heading ``yaw``) by ``width`` (m), centred on (``x``, ``y``).

    Examples
    --------
    >>> box = Box("crate", x=2.0, y=0.0, length=1.0, width=0.5)
    >>> box.entry([[0.0, 0.0]], [[1.0, 0.0]]).tolist()      # the near face is at x = 1.5
    [1.5]
    >>> box.depth([[2.0, 0.0], [2.0, 1.0]]).tolist()          # the centre: 0.25 m inside; 0.75 m out
    [0.25, -0.75]
    """

    name: str
    x: float
    y: float
    length: float
    width: float
    yaw: float = 0.0
    start: float = -math.inf
    end: float = math.inf

    def __post_init__(self):
        _check("Box", self, {"length": self.length, "width": self.width})

    @property
    def size(self) -> float:
        """The largest extent (m): the diagonal."""
        return math.hypot(self.length, self.width)

    def _local(self, points) -> np.ndarray:
        """Points in the box's frame (its centre the origin, x along its length)."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        p = _points(points) - (self.x, self.y)
        return np.c_[c * p[:, 0] + s * p[:, 1], -s * p[:, 0] + c * p[:, 1]]

    def _world(self, local) -> np.ndarray:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return np.c_[c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]] + (self.x, self.y)

    def _half(self) -> np.ndarray:
        return np.array([self.length / 2, self.width / 2])

    def entry(self, origins, directions) -> np.ndarray:
        """Distance along each ray (unit ``directions``) to the box's surface; ``inf`` if it misses, 0 inside."""
        o = self._local(origins)
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        d = _points(directions)
        d = np.c_[c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]]
        half = self._half()
        near = np.full(len(o), -np.inf)
        far = np.full(len(o), np.inf)
        for axis in range(2):
            moving = d[:, axis] != 0
            with np.errstate(divide="ignore", invalid="ignore"):
                t1 = (-half[axis] - o[:, axis]) / d[:, axis]
                t2 = (half[axis] - o[:, axis]) / d[:, axis]
            low = np.where(moving, np.minimum(t1, t2), np.where(np.abs(o[:, axis]) <= half[axis], -np.inf, np.inf))
            high = np.where(moving, np.maximum(t1, t2), np.where(np.abs(o[:, axis]) <= half[axis], np.inf, -np.inf))
            near, far = np.maximum(near, low), np.minimum(far, high)
        hit = (near <= far) & (far >= 0)
        return np.where(hit, np.maximum(near, 0.0), np.inf)

    def closest(self, points) -> np.ndarray:
        """The box's nearest point to each point (the point itself inside)."""
        half = self._half()
        return self._world(np.clip(self._local(points), -half, half))

    def depth(self, points) -> np.ndarray:
        """How far inside the box each point lies (m); negative: its distance outside."""
        q = np.abs(self._local(points)) - self._half()
        outside = np.hypot(np.maximum(q[:, 0], 0), np.maximum(q[:, 1], 0))
        return np.where(outside > 0, -outside, -np.max(q, axis=1))

    def outline(self) -> np.ndarray:
        """The corners, counter-clockwise, the first repeated at the end (for drawing)."""
        hx, hy = self._half()
        return self._world(np.array([[hx, hy], [-hx, hy], [-hx, -hy], [hx, -hy], [hx, hy]]))


@dataclass(frozen=True)
class Cylinder(_Timed):
    """An upright cylinder of ``radius`` (m) on (``x``, ``y``): a circle in the scan's plane.

    Examples
    --------
    >>> bin_ = Cylinder("bin", x=0.0, y=3.0, radius=0.5)
    >>> bin_.entry([[0.0, 0.0], [1.0, 0.0]], [[0.0, 1.0], [0.0, 1.0]]).tolist()
    [2.5, inf]
    """

    name: str
    x: float
    y: float
    radius: float
    start: float = -math.inf
    end: float = math.inf

    def __post_init__(self):
        _check("Cylinder", self, {"radius": self.radius})

    @property
    def size(self) -> float:
        """The largest extent (m): the diameter."""
        return 2 * self.radius

    def entry(self, origins, directions) -> np.ndarray:
        """Distance along each ray (unit ``directions``) to the circle; ``inf`` if it misses, 0 inside.

        ``|o + t u - c|^2 = r^2`` with ``|u| = 1``: ``t = -b - sqrt(b^2 - k)``,
        ``b = u . (o - c)``, ``k = |o - c|^2 - r^2``.
        """
        oc = _points(origins) - (self.x, self.y)
        u = _points(directions)
        b = np.sum(u * oc, axis=1)
        k = np.sum(oc * oc, axis=1) - self.radius ** 2
        disc = b * b - k
        with np.errstate(invalid="ignore"):
            t = -b - np.sqrt(disc)
        inside = k <= 0
        ahead = (disc >= 0) & (t >= 0)
        return np.where(inside, 0.0, np.where(ahead, t, np.inf))

    def closest(self, points) -> np.ndarray:
        """The disc's nearest point to each point (the point itself inside)."""
        p = _points(points)
        v = p - (self.x, self.y)
        d = np.hypot(v[:, 0], v[:, 1])
        scale = np.where(d > self.radius, self.radius / np.where(d > 0, d, 1.0), 1.0)
        return (self.x, self.y) + v * scale[:, None]

    def depth(self, points) -> np.ndarray:
        """How far inside the disc each point lies (m); negative: its distance outside."""
        v = _points(points) - (self.x, self.y)
        return self.radius - np.hypot(v[:, 0], v[:, 1])

    def outline(self, n: int = 48) -> np.ndarray:
        """Points around the circle, the first repeated at the end (for drawing)."""
        a = np.linspace(0, 2 * math.pi, n + 1)
        return np.c_[self.x + self.radius * np.cos(a), self.y + self.radius * np.sin(a)]


@dataclass(frozen=True)
class Wall(_Timed):
    """A wall segment from (``x1``, ``y1``) to (``x2``, ``y2``), ``thickness`` m thick: a thin box.

    Examples
    --------
    >>> wall = Wall("panel", x1=1.0, y1=-1.0, x2=1.0, y2=1.0, thickness=0.1)
    >>> wall.entry([[0.0, 0.0]], [[1.0, 0.0]]).round(3).tolist()
    [0.95]
    """

    name: str
    x1: float
    y1: float
    x2: float
    y2: float
    thickness: float = 0.1
    start: float = -math.inf
    end: float = math.inf

    def __post_init__(self):
        _check("Wall", self, {"length": math.hypot(self.x2 - self.x1, self.y2 - self.y1),
                              "thickness": self.thickness})

    @property
    def box(self) -> Box:
        """The wall as a box: centred on the segment's middle, its length the segment's."""
        return Box(self.name, (self.x1 + self.x2) / 2, (self.y1 + self.y2) / 2,
                   math.hypot(self.x2 - self.x1, self.y2 - self.y1), self.thickness,
                   math.atan2(self.y2 - self.y1, self.x2 - self.x1), self.start, self.end)

    @property
    def x(self) -> float:
        return (self.x1 + self.x2) / 2

    @property
    def y(self) -> float:
        return (self.y1 + self.y2) / 2

    @property
    def size(self) -> float:
        return self.box.size

    def entry(self, origins, directions) -> np.ndarray:
        """Distance along each ray to the wall's surface (:meth:`Box.entry`)."""
        return self.box.entry(origins, directions)

    def closest(self, points) -> np.ndarray:
        """The wall's nearest point to each point (:meth:`Box.closest`)."""
        return self.box.closest(points)

    def depth(self, points) -> np.ndarray:
        """How far inside the wall each point lies (:meth:`Box.depth`)."""
        return self.box.depth(points)

    def outline(self) -> np.ndarray:
        """The wall's corners (for drawing)."""
        return self.box.outline()


#: The kinds of object by the name a file or a command line gives them.
SHAPES = {"box": Box, "cylinder": Cylinder, "wall": Wall}
