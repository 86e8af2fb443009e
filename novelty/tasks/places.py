"""Places and visits from a robot's poses: which scans meet a place again.

A robot that drives through a building meets places for the first time and
again. From the poses alone (no scan is looked at):

- :func:`leader_places` gives every scan a *place*: taken in driving order, a
  scan whose pose is farther than ``radius`` from every place founded so far
  (or faces more than ``max_turn`` away from each near one) founds a new
  place at its pose; any other scan belongs to the nearest place it faces.
  This is the leader algorithm of clustering (Hartigan 1975, section 3.2)
  run on the poses in the order driven, so a place exists from the moment
  the robot first stands there.
- :func:`place_visits` counts the robot's *visits* of each scan's place
  before the scan: a visit ends when the robot goes farther than ``leave``
  from the place, so a pass through a place is one visit however many scans
  it holds.
- :func:`revisit_task` makes of them an exploration task: places met after
  the warm-up are tracked features, a scan's exposure is its place's visits
  before it.

This module shares its name with :mod:`novelty.tasks.objects.places` (whether an
object's place was seen before it appeared): both are about places, one of a drive, one of an object.

References
----------
Hartigan, J. A. (1975). Clustering Algorithms. Wiley, New York.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..data import Dataset
from ..io.recording.readers import read_recording
from ..io.recording.reading import Reading
from ..sonar.preprocessing import PAPER_THRESHOLD
from .exploration.runs import from_runs

__all__ = ["leader_places", "place_visits", "revisit_task", "finite_positions"]


def _poses(poses) -> np.ndarray:
    p = np.asarray(poses, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] < 2 or not np.all(np.isfinite(p)):
        raise ValueError(f"poses must be finite rows of (x, y) or (x, y, theta); got shape {p.shape}.")
    return p


def finite_positions(poses) -> np.ndarray:
    """The (x, y) of every pose; a non-finite one is refused (it has no place on a grid or a path)."""
    p = np.asarray(poses, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] < 2:
        raise ValueError(f"poses must be rows of (x, y) or (x, y, theta); got shape {p.shape}.")
    bad = np.flatnonzero(~np.all(np.isfinite(p[:, :2]), axis=1))
    if bad.size:
        raise ValueError(f"pose {bad[0]} is {p[bad[0]].tolist()}; positions must be finite.")
    return p[:, :2]


def _turn(a, b):
    """The absolute difference of headings ``a`` and ``b`` (rad), in [0, pi]."""
    return np.abs((np.asarray(a) - b + np.pi) % (2 * np.pi) - np.pi)


def leader_places(poses, radius: float, max_turn: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The place of every scan and the places' founding poses.

    Parameters
    ----------
    poses : array-like of shape (n_scans, 2) or (n_scans, 3)
        x, y (m) and, with ``max_turn``, the heading theta (rad), in the order driven.
    radius : float
        A scan within ``radius`` (m) of a place's founding pose may belong to it.
    max_turn : float, optional
        With it, a scan belongs to a place only if its heading is within
        ``max_turn`` (rad) of the founding scan's: a forward-looking sensor
        sees another side of a place it faces away from.

    Returns
    -------
    place : ndarray of int, shape (n_scans,)
        The index of each scan's place (places numbered in the order founded).
    founders : ndarray of int
        The scan that founded each place.

    Examples
    --------
    >>> x = [0.0, 0.5, 1.5, 4.0, 1.4, 0.2]            # out along a line and back
    >>> place, founders = leader_places(np.c_[x, np.zeros(6)], radius=1.0)
    >>> place.tolist(), founders.tolist()
    ([0, 0, 1, 2, 1, 0], [0, 2, 3])
    """
    p = _poses(poses)
    if not radius > 0:
        raise ValueError(f"radius must be a positive length (m); got {radius!r}.")
    if max_turn is not None and (p.shape[1] < 3 or not 0 < max_turn <= np.pi):
        raise ValueError(f"max_turn needs headings (poses of x, y, theta) and must be in (0, pi]; "
                         f"got {max_turn!r} with poses of shape {p.shape}.")
    place = np.empty(len(p), dtype=np.int64)
    founders: list[int] = []
    for i, pose in enumerate(p):
        centres = p[founders]
        d = np.hypot(centres[:, 0] - pose[0], centres[:, 1] - pose[1]) if founders else np.empty(0)
        ok = d <= radius
        if max_turn is not None and founders:
            ok &= _turn(centres[:, 2], pose[2]) <= max_turn
        if ok.any():
            place[i] = int(np.flatnonzero(ok)[np.argmin(d[ok])])
        else:
            place[i] = len(founders)
            founders.append(i)
    return place, np.array(founders, dtype=np.int64)


def place_visits(poses, place, founders, leave: float) -> np.ndarray:
    """How many earlier visits of its place each scan's visit follows (0: the first visit).

    A visit of a place ends when the robot goes farther than ``leave`` (m)
    from the place's founding pose; the next scan of that place begins a new
    visit.

    Examples
    --------
    >>> x = [0.0, 0.5, 1.5, 4.0, 1.4, 0.2]
    >>> poses = np.c_[x, np.zeros(6)]
    >>> place, founders = leader_places(poses, radius=1.0)
    >>> place_visits(poses, place, founders, leave=2.0).tolist()
    [0, 0, 0, 0, 1, 1]
    """
    p = _poses(poses)
    place = np.asarray(place, dtype=np.int64)
    founders = np.asarray(founders, dtype=np.int64)
    if place.shape != (len(p),):
        raise ValueError(f"place has shape {place.shape}; expected ({len(p)},), one place a scan.")
    visits = np.zeros(len(p), dtype=np.int64)
    count = np.zeros(len(founders), dtype=np.int64)     # visits of each place begun so far
    last = np.full(len(founders), -1, dtype=np.int64)   # the place's latest scan
    for i, c in enumerate(place.tolist()):
        if last[c] >= 0:
            between = p[last[c] + 1:i, :2] - p[founders[c], :2]
            if between.size and np.hypot(between[:, 0], between[:, 1]).max() > leave:
                count[c] += 1
        else:
            count[c] = 0
        visits[i], last[c] = count[c], i
    return visits


def revisit_task(path, topic=None, *, radius: float = 1.0, leave: float | None = None, max_turn: float | None = None,
                 run_scans: int = 100, warmup: int = 1, name: str | None = None,
                 threshold: float = PAPER_THRESHOLD, sectors: int = 16, reduce="min", clip: float | None = None,
                 pose_topic: str | None = None, seed: int = 0) -> Dataset:
    """An exploration task from one recording with poses: places met for the first time, and again.

    The places are :func:`leader_places` of the poses (``radius``,
    ``max_turn``); the recording is cut into runs of ``run_scans`` scans (a
    last shorter block joins the run before it). The places founded in the
    first ``warmup`` runs are the familiar environment (untracked: their scans
    are the familiar scans); every later place is a tracked feature, and a
    scan's *exposure* is the number of earlier visits of its place
    (:func:`place_visits`, a visit ending when the robot goes farther than
    ``leave``, default ``2 * radius``): 0 on the first visit, so ``y`` = 1
    there. Exposures count visits rather than runs, since one run may pass
    a place twice.

    Parameters
    ----------
    path, topic, threshold, sectors, reduce, clip, pose_topic
        The recording and how its scans become rings, as
        :func:`novelty.io.read_recording`.
    radius, leave, max_turn
        Places and visits (m, m, rad), as :func:`leader_places` and :func:`place_visits`.
    run_scans : int, default=100
        Scans a run.
    warmup : int, default=1
        The first runs, learned before anything is tracked.
    name : str, optional
        The task's name (default: the file's).
    seed : int, default=0
        Unused: a recording is what it is (the benchmark gives every task a seed).

    Returns
    -------
    Dataset
        As :func:`novelty.tasks.exploration.from_runs` (``columns["exposure"]``
        counting visits), plus ``poses``, ``columns["time"]``,
        ``columns["place"]`` (every scan's place, familiar ones too) and
        ``columns["visit"]`` (every scan's visits before, familiar ones too).
    """
    for label, v, low in (("run_scans", run_scans, 1), ("warmup", warmup, 1)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
            raise ValueError(f"{label} must be an int >= {low}; got {v!r}.")
    leave = 2.0 * radius if leave is None else leave
    if not leave >= radius:
        raise ValueError(f"leave ({leave!r}) must be at least radius ({radius!r}).")
    data = read_recording(path, Reading(topic=topic, threshold=threshold, sectors=sectors, reduce=reduce, clip=clip,
                                        pose_topic=pose_topic))
    if data.poses is None:
        raise ValueError(f"{data.name} has no poses; places need them (give pose_topic=).")
    place, founders = leader_places(data.poses, radius, max_turn)
    visit = place_visits(data.poses, place, founders, leave)
    n_runs = len(data) // run_scans
    if n_runs <= warmup:
        raise ValueError(f"{data.name} has {len(data)} scans: {n_runs} runs of {run_scans}, not more than "
                         f"warmup={warmup}; use shorter runs.")
    run = np.minimum(np.arange(len(data)) // run_scans, n_runs - 1)
    familiar = np.isin(place, place[run < warmup])
    labels = ["" if familiar[i] else f"place {place[i]}" for i in range(len(data))]
    cuts = np.flatnonzero(np.diff(run)) + 1
    task = from_runs(np.split(data.X, cuts), np.split(np.array(labels, dtype=object), cuts), warmup=warmup,
                     name=name or data.name, environments=[f"{data.name}#{r}" for r in range(n_runs)])
    exposure = np.where(familiar, -1, visit)
    meta = dict(task.metadata, source=str(path), threshold_m=float(threshold), sectors=sectors, reduce=reduce,
                places={"radius_m": float(radius), "leave_m": float(leave), "max_turn_rad": max_turn,
                        "n_places": int(len(founders)), "familiar_places": int(len(set(place[run < warmup])))},
                run_scans=int(run_scans), encoding="1 - min(r, T) / T",
                labels="y = 1 where a scan visits a place not met before (a place founded after the warm-up)",
                description=f"A robot's drive ({data.name}): places met for the first time and again.")
    return replace(task, y=(exposure == 0).astype(np.int64), poses=data.poses, metadata=meta,
                   columns=dict(task.columns, exposure=exposure, time=data.columns["time"], place=place,
                                visit=visit))
