"""Whether an object stands in a place the robot had seen before it appeared.

A place is **seen** when, before the object appears, a beam of the robot
passed through or ended in the object's footprint grown by ``tolerance``
on every side (one 0.1 m cell by default; a box's corners stay square).
Only the part of each beam within ``within`` counts: the range the task's
rows see (the ring's threshold). A beam that returned nothing (``nan``) saw
nothing; one recorded as ``inf`` (nothing within the sensor's reach) passed
through ``within`` of free space. A sonar's beam is its cone's axis.

A detector that learns places (a map of cells) can only tell a changed
place from a new one when the place was seen: the objects tasks label each
object with it (:func:`looks`), and the benchmarks report the objects in
seen and unseen places apart.

This module shares its name with :mod:`novelty.tasks.places` (places met
again from the poses): both are about places, one of a drive, one of an object.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Sequence

import numpy as np

from .raycast import world_beams
from .shapes import Box, Cylinder, Wall

__all__ = ["grown", "looks", "PLACE_TOLERANCE"]

#: How far (m) a beam may pass beside an object's footprint and still have seen its place: one 0.1 m cell.
PLACE_TOLERANCE = 0.1


def grown(obj, tolerance: float):
    """``obj`` grown by ``tolerance`` (m) on every side: a cylinder's radius, a box's (or wall's) length and width.

    >>> grown(Box("b", 0.0, 0.0, 1.0, 0.5), 0.1).length, grown(Cylinder("c", 0.0, 0.0, 0.2), 0.1).radius
    (1.2, 0.30000000000000004)
    """
    if not tolerance >= 0:
        raise ValueError(f"tolerance must be a length >= 0 (m); got {tolerance!r}.")
    if isinstance(obj, Wall):
        obj = obj.box
    if isinstance(obj, Cylinder):
        return replace(obj, radius=obj.radius + tolerance)
    if isinstance(obj, Box):
        return replace(obj, length=obj.length + 2 * tolerance, width=obj.width + 2 * tolerance)
    raise TypeError(f"Objects are a Box, Cylinder or Wall; got {type(obj).__name__}.")


def _looked(sweep, footprint, within: float) -> bool:
    """Whether a beam of ``sweep`` passed through or ended in ``footprint`` within ``within`` of its origin."""
    origins, angles = world_beams(sweep)
    r = np.asarray(sweep.ranges, dtype=np.float64)
    known = ~np.isnan(r)
    if not known.any():
        return False
    length = np.minimum(r[known], within)
    entry = footprint.entry(origins[known], np.c_[np.cos(angles[known]), np.sin(angles[known])])
    return bool(np.any(entry <= length))


def looks(sweeps: Sequence, objects: Sequence, *, tolerance: float = PLACE_TOLERANCE,
          within: float = math.inf) -> np.ndarray:
    """How many of ``sweeps`` saw each object's place before it appeared (module docstring).

    A sweep counts for an object when it was taken before the object's
    ``start`` and one of its beams passed through or ended in the object's
    footprint grown by ``tolerance``, within ``within`` (m) of the beam's
    origin. The place is seen when the count is above 0.

    Returns
    -------
    ndarray of int, shape (n_objects,)
    """
    if not within > 0:
        raise ValueError(f"within must be a positive length (m); got {within!r}.")
    footprints = [grown(o, tolerance) for o in objects]
    counts = np.zeros(len(footprints), dtype=np.int64)
    for sweep in sweeps:
        for k, (obj, footprint) in enumerate(zip(objects, footprints)):
            if sweep.time < obj.start and _looked(sweep, footprint, within):
                counts[k] += 1
    return counts
