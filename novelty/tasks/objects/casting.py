"""Which scans saw which object, and the robot's passes of each: first sight and every later exposure.

:func:`cast_all` casts the objects into every sweep of a recording
(:func:`~novelty.tasks.objects.raycast.inject`) and keeps, per scan and per
object, the number of beams the object changed. A scan **sees** an object
when at least ``min_beams`` of its beams were changed (:func:`sightings`).
A **pass** of an object is a stretch of the drive in which the robot sees
it: it ends when the robot goes farther than ``leave`` from the object, so
that a scan or two in which a person hides the object, or the robot turns
on the spot, do not start a new one (:func:`passes`). The first pass is
the object's first exposure, the k-th its k-th.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np

from .raycast import inject

__all__ = ["Cast", "cast_all", "sightings", "passes"]


@dataclass(frozen=True, eq=False)
class Cast:
    """A recording with objects cast into it.

    Attributes
    ----------
    sweeps : list of Sweep
        The new sweeps, one a recorded sweep, in order.
    shortened : ndarray of int, shape (n_scans, n_objects)
        The beams each object changed in each scan.
    recorded : list of Sweep
        The sweeps as recorded.
    objects : tuple
        The objects, in the order of ``shortened``'s columns.
    """

    sweeps: list
    shortened: np.ndarray
    recorded: list
    objects: tuple

    @property
    def times(self) -> np.ndarray:
        return np.array([s.time for s in self.recorded], dtype=np.float64)

    @property
    def poses(self) -> np.ndarray:
        return np.array([s.pose for s in self.recorded], dtype=np.float64)


def cast_all(sweeps: Iterable, objects: Sequence, *, margin: float = 0.1, within: float = math.inf,
             max_range: float = math.inf) -> Cast:
    """Cast ``objects`` into every sweep (:func:`~novelty.tasks.objects.raycast.inject`, same options)."""
    objects = tuple(objects)
    names = [o.name for o in objects]
    if len(set(names)) != len(names):
        raise ValueError(f"Objects need distinct names; got {names}.")
    recorded, new, counts = [], [], []
    for sweep in sweeps:
        out = inject(sweep, objects, margin=margin, within=within, max_range=max_range)
        recorded.append(sweep)
        new.append(out.sweep)
        counts.append(out.shortened)
    if not recorded:
        raise ValueError("No sweeps to cast the objects into.")
    shortened = np.array(counts, dtype=np.int64).reshape(len(recorded), len(objects))
    return Cast(new, shortened, recorded, objects)


def sightings(shortened, min_beams: int = 3) -> np.ndarray:
    """Whether each scan sees each object: at least ``min_beams`` beams changed.

    >>> sightings([[0, 5], [3, 1]], min_beams=3).tolist()
    [[False, True], [True, False]]
    """
    if isinstance(min_beams, bool) or not isinstance(min_beams, (int, np.integer)) or min_beams < 1:
        raise ValueError(f"min_beams must be an int >= 1; got {min_beams!r}.")
    return np.asarray(shortened) >= min_beams


def passes(seen, poses, obj, leave: float) -> np.ndarray:
    """The pass of each scan that sees ``obj`` (0 the first), -1 for scans that do not.

    A pass ends when the robot (its pose's x, y) goes farther than
    ``leave`` (m) from the object's nearest point; the next scan that sees
    it begins a new pass.

    Examples
    --------
    >>> from novelty.tasks.objects.shapes import Cylinder
    >>> x = [0.0, 1.0, 2.0, 9.0, 2.0, 1.0, 1.5]        # by the object, away, back
    >>> seen = [True, True, False, False, True, False, True]
    >>> passes(seen, np.c_[x, np.zeros(7)], Cylinder("c", 1.0, 1.0, 0.2), leave=4.0).tolist()
    [0, 0, -1, -1, 1, -1, 1]
    """
    seen = np.asarray(seen, dtype=bool)
    p = np.asarray(poses, dtype=np.float64)[:, :2]
    if seen.shape != (len(p),):
        raise ValueError(f"seen has shape {seen.shape}; expected ({len(p)},), one entry a pose.")
    if not leave > 0:
        raise ValueError(f"leave must be a positive length (m); got {leave!r}.")
    gone = np.hypot(*(obj.closest(p) - p).T) > leave
    out = np.full(len(p), -1, dtype=np.int64)
    count, left = -1, True
    for i in range(len(p)):
        left = left or bool(gone[i])
        if seen[i]:
            if left:
                count, left = count + 1, False
            out[i] = count
    return out
