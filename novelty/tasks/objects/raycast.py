"""Virtual objects cast into a recorded sweep: each beam's range becomes the nearer of the two.

A :class:`~novelty.io.ros.messages.Sweep` holds a whole scan in the robot's base
frame, every beam with its origin and direction (the sensor's mount
included) and the base frame's pose in the world. :func:`inject` moves
each beam into the world frame (origin ``pose_xy + R(yaw) origin``,
direction ``yaw + angle``), asks each object present at the sweep's time
how far along the beam its surface is, and gives the beam the nearer of
that and its recorded range: an object in front of what was recorded hides
it, one behind it stays hidden (physically consistent occlusion, objects
occluding each other alike). The result is a new sweep with the same
geometry, which :func:`~novelty.io.scans.sweep_rings.sweep_ring` turns into a ring.

A laser beam is a ray. A beam with a ``spread`` (a sonar's cone, its full
angle) reports its nearest echo: the nearest point of an object within the
cone (:func:`cone_range`), the cone model of sonar sensing (Kuc & Siegel
1987; Leonard & Durrant-Whyte 1992, chapter 2; specular reflections are
left out).

What the recording said: a range is kept where no object is nearer. A beam
that recorded nothing (``+inf``) or no information (NaN) takes the
object's range where an object is in its way within ``max_range``: a
solid object in front of the sensor is what the sensor sees.

Labels: the object *changed what the sensor saw* on a beam when the beam's
new range is the object's and is shorter than the recorded one by more
than ``margin`` (a beam that recorded ``+inf`` or NaN counts as infinitely
long); only beams whose new range is within ``within`` count (what the ring
keeps, e.g. the paper's 4 m threshold). :func:`inject` returns that count
per object; a scan *sees* an object when the count reaches a stated number
of beams (:func:`novelty.tasks.objects.casting.sightings`).

References
----------
Kuc, R. & Siegel, M. W. (1987). Physically based simulation model for
acoustic sensor robot navigation. IEEE PAMI 9(6), 766-778.
Leonard, J. J. & Durrant-Whyte, H. F. (1992). Directed Sonar Sensing for
Mobile Robot Navigation. Kluwer (the cone of a sonar's nearest echo).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

__all__ = ["Injection", "world_beams", "beam_ranges", "cone_range", "inject"]


@dataclass(frozen=True, eq=False)
class Injection:
    """A sweep with the objects cast into it, and how many of its beams each object changed.

    Attributes
    ----------
    sweep : Sweep
        The new sweep: the same geometry, its ranges the nearer of the
        recorded ones and the objects'.
    shortened : ndarray of int, shape (n_objects,)
        For each object (in the order given), the beams it changed: its
        range the beam's new range, shorter than the recorded one by more
        than ``margin``, within ``within``.
    nearest : ndarray of int, shape (n_beams,)
        Which object each beam now ends on (-1: the recorded surface).
    """

    sweep: object
    shortened: np.ndarray
    nearest: np.ndarray


def world_beams(sweep) -> tuple[np.ndarray, np.ndarray]:
    """Every beam's origin (m) and direction (rad) in the world frame, from the sweep's pose."""
    if sweep.pose is None:
        raise ValueError(f"The sweep at t={sweep.time} has no pose: objects stand in the world frame, so "
                         "their beams need the robot's pose (give the recording's poses, pose_topic=).")
    x, y, yaw = (float(v) for v in sweep.pose)
    c, s = math.cos(yaw), math.sin(yaw)
    o = np.asarray(sweep.origins, dtype=np.float64).reshape(-1, 2)
    origins = np.c_[x + c * o[:, 0] - s * o[:, 1], y + s * o[:, 0] + c * o[:, 1]]
    return origins, yaw + np.asarray(sweep.angles, dtype=np.float64)


def _unit(angles) -> np.ndarray:
    return np.c_[np.cos(angles), np.sin(angles)]


def cone_range(obj, origins, angles, spread) -> np.ndarray:
    """The nearest point of a convex object within each cone: a sonar's nearest echo (m; ``inf`` none).

    The cone of beam ``i`` holds the directions within ``spread[i] / 2`` of
    ``angles[i]``. Over a convex object and a convex cone the distance to the
    origin is least either at the object's point nearest the origin, when it
    lies within the cone, or on one of the cone's two edges, where it is the
    edge ray's entry into the object. A cone wider than pi (not convex) is
    cut into convex parts.

    Examples
    --------
    >>> from novelty.tasks.objects.shapes import Cylinder
    >>> pole = Cylinder("pole", x=2.0, y=1.0, radius=0.5)
    >>> # a ray along x misses it; a cone of 90 degrees sees its nearest point, sqrt(5) - 0.5 away
    >>> cone_range(pole, [[0.0, 0.0]], [0.0], [0.0]).tolist(), cone_range(pole, [[0.0, 0.0]], [0.0], [np.pi / 2]).round(4).tolist()
    ([inf], [1.7361])
    """
    o = np.asarray(origins, dtype=np.float64).reshape(-1, 2)
    a = np.asarray(angles, dtype=np.float64).reshape(-1)
    w = np.broadcast_to(np.asarray(spread, dtype=np.float64), a.shape)
    out = np.full(len(a), np.inf)
    ray = w <= 0
    if ray.any():
        out[ray] = obj.entry(o[ray], _unit(a[ray]))
    cone = np.flatnonzero(~ray)
    if cone.size:
        parts = np.maximum(np.ceil(w[cone] / math.pi), 1).astype(int)
        for k in np.unique(parts).tolist():
            pick = cone[parts == k]
            width = w[pick] / k
            for j in range(k):   # convex sub-cones side by side, centred on the beam together
                centre = a[pick] - w[pick] / 2 + (j + 0.5) * width
                out[pick] = np.minimum(out[pick], _convex_cone(obj, o[pick], centre, width))
    return out


def _convex_cone(obj, o, centre, width) -> np.ndarray:
    near = obj.closest(o)
    v = near - o
    d = np.hypot(v[:, 0], v[:, 1])
    off = np.abs((np.arctan2(v[:, 1], v[:, 0]) - centre + math.pi) % (2 * math.pi) - math.pi)
    inside_cone = (d == 0) | (off <= width / 2 + 1e-12)
    edges = np.minimum(obj.entry(o, _unit(centre - width / 2)), obj.entry(o, _unit(centre + width / 2)))
    return np.where(inside_cone, d, edges)


def beam_ranges(obj, sweep) -> np.ndarray:
    """How far along each beam of ``sweep`` the object's surface is (m; ``inf`` where it misses or is absent)."""
    if not obj.present(sweep.time):
        return np.full(len(sweep.ranges), np.inf)
    origins, angles = world_beams(sweep)
    spread = np.zeros(len(angles)) if getattr(sweep, "spread", None) is None else sweep.spread
    return cone_range(obj, origins, angles, spread)


def inject(sweep, objects: Sequence, *, margin: float = 0.1, within: float = math.inf,
           max_range: float = math.inf) -> Injection:
    """Cast ``objects`` into ``sweep``: the new sweep and the beams each object changed (module docstring).

    Parameters
    ----------
    sweep : Sweep
        A recorded sweep with its pose.
    objects : sequence of Box, Cylinder or Wall
        Those present at ``sweep.time`` are cast.
    margin : float, default=0.1
        A beam counts as changed by an object when shortened by more than this (m).
    within : float, default=inf
        Only beams whose new range is within this (m) count (the ring's threshold).
    max_range : float, default=inf
        The sensor's reach (m): an object farther along a beam is not seen.

    Examples
    --------
    >>> from novelty.io.scans.sweeps import Sweep
    >>> from novelty.tasks.objects.shapes import Box
    >>> corridor = Sweep(0.0, np.zeros((3, 2)), np.array([-0.5, 0.0, 0.5]), np.array([2.0, np.inf, 2.0]), np.zeros(3))
    >>> out = inject(corridor, [Box("crate", x=1.0, y=0.0, length=0.2, width=0.2)])
    >>> out.sweep.ranges.tolist(), out.shortened.tolist()
    ([2.0, 0.9, 2.0], [1])
    """
    for name, value, low in (("margin", margin, 0.0), ("within", within, 0.0), ("max_range", max_range, 0.0)):
        if not (isinstance(value, (int, float)) and value >= low and not math.isnan(value)):
            raise ValueError(f"{name} must be a length >= {low} (m); got {value!r}.")
    recorded = np.asarray(sweep.ranges, dtype=np.float64)
    ranges = np.full((len(objects), len(recorded)), np.inf)
    for k, obj in enumerate(objects):
        ranges[k] = beam_ranges(obj, sweep)
    ranges[ranges > max_range] = np.inf
    nearest = np.argmin(ranges, axis=0) if len(objects) else np.zeros(len(recorded), dtype=np.intp)
    best = ranges[nearest, np.arange(len(recorded))] if len(objects) else np.full(len(recorded), np.inf)
    long = np.where(np.isnan(recorded), np.inf, recorded)     # nothing or no information: no surface in the way
    wins = best < long
    new = np.where(wins, best, recorded)
    changed = wins & (best < long - margin) & (best <= within)
    nearest = np.where(wins, nearest, -1)
    shortened = np.array([np.count_nonzero(changed & (nearest == k)) for k in range(len(objects))], dtype=np.int64)
    return Injection(replace(sweep, ranges=new), shortened, nearest)
