"""Runs, marked features and novelty tasks from robot recordings.

A recording is split into runs (:func:`split_runs`: by file, by gaps in
time, or by the user's time intervals); the features a scan perceives are
marked from the user's CSV (:func:`read_marks`, :func:`mark_features`: "the
box stood here from t1 to t2") or are the places of a grid over the robot's
poses (:func:`place_features`); :func:`recording_task` makes of them an
exploration task (:func:`novelty.exploration.from_runs`: each scan's tracked
feature and its exposure count), which is also a hold-out task (learn the
warm-up runs, score the rest; ``y`` = 1 at a feature's first exposure). The
task carries the poses and times, so novelty can be drawn on the robot's
path. It is the registered dataset ``recording``.

:func:`visit_counts` says, from the poses alone, how often the robot had
been at each scan's place before: the ground truth of a robot exploring a
building, whose novelty should fall as places recur.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Sequence

import numpy as np

from ..data import Dataset
from ..datasets.exploration.runs import from_runs
from .places import finite_positions
from ..io.recording.readers import read_recording, read_sweeps
from ..io.recording.reading import Reading, reading_given, reading_of, takes_reading_options
from ..io.scans.points import points_columns, sweep_points

__all__ = ["Mark", "read_marks", "mark_features", "place_features", "split_runs", "visit_counts",
           "recording_task"]

_MARK_COLUMNS = ("feature", "start", "end", "x", "y", "radius")
_PLACE = "place "   # the prefix of a grid place's feature id


@dataclass(frozen=True)
class Mark:
    """A feature the robot perceives during a time interval, within a region, or both.

    A scan perceives the feature when its time is in [``start``, ``end``]
    (if given) and the robot is within ``radius`` metres of (``x``, ``y``)
    (if given).
    """

    feature: str
    start: float = -math.inf
    end: float = math.inf
    x: float | None = None
    y: float | None = None
    radius: float | None = None


def read_marks(path) -> list[Mark]:
    """The marks of a CSV file with a header: ``feature`` and ``start,end`` (s) and/or ``x,y,radius`` (m).

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "marks.csv")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("feature,start,end,x,y,radius\\nbox,10,20,,,\\ndoor,,,1.5,2,0.5\\n")
    >>> [(m.feature, m.start, m.radius) for m in read_marks(path)]
    [('box', 10.0, None), ('door', -inf, 0.5)]
    """
    with open(path, newline="", encoding="utf-8") as fh:
        rows = csv.reader(fh)
        header = [h.strip() for h in next(rows, [])]
        unknown = sorted(set(header) - set(_MARK_COLUMNS))
        if "feature" not in header or unknown:
            raise ValueError(f"{path}: the header must name 'feature' and some of start, end, x, y, radius; "
                             f"got {header}.")
        marks = [_mark(dict(zip(header, (c.strip() for c in row))), path, line)
                 for line, row in enumerate(rows, start=2) if any(c.strip() for c in row)]
    if not marks:
        raise ValueError(f"{path}: no marks (one row a feature after the header).")
    return marks


def _mark(row: dict, path, line: int) -> Mark:
    def number(name):
        text = row.get(name, "")
        if text == "":
            return None
        try:
            return float(text)
        except ValueError:
            raise ValueError(f"{path}, line {line}: {name} is {text!r}, not a number.") from None

    start, end, x, y, radius = (number(n) for n in ("start", "end", "x", "y", "radius"))
    if not row.get("feature"):
        raise ValueError(f"{path}, line {line}: no feature name.")
    region = (x, y, radius)
    if any(v is None for v in region) and any(v is not None for v in region):
        raise ValueError(f"{path}, line {line}: a region needs x, y and radius.")
    if radius is not None and not radius > 0:
        raise ValueError(f"{path}, line {line}: radius must be positive; got {radius}.")
    if start is None and end is None and x is None:
        raise ValueError(f"{path}, line {line}: give a time interval (start, end) or a region (x, y, radius).")
    start = -math.inf if start is None else start
    end = math.inf if end is None else end
    if end < start:
        raise ValueError(f"{path}, line {line}: end {end} is before start {start}.")
    return Mark(row["feature"], start, end, x, y, radius)


def mark_features(marks: Sequence[Mark], time, poses=None) -> list[tuple[str, ...]]:
    """The features each scan perceives, by its time and (for regions) its pose.

    Examples
    --------
    >>> marks = [Mark("box", 1.0, 2.0), Mark("door", x=0.0, y=0.0, radius=1.0)]
    >>> mark_features(marks, [0.5, 1.5, 3.0], [[0.0, 0.5, 0.0], [5.0, 5.0, 0.0], [0.0, -0.9, 0.0]])
    [('door',), ('box',), ('door',)]
    """
    time = np.asarray(time, dtype=np.float64)
    seen = [set() for _ in range(len(time))]
    for mark in marks:
        inside = (time >= mark.start) & (time <= mark.end)
        if mark.radius is not None:
            if poses is None:
                raise ValueError(f"Mark {mark.feature!r} is a region, but the recording has no poses.")
            p = np.asarray(poses, dtype=np.float64)
            inside &= np.hypot(p[:, 0] - mark.x, p[:, 1] - mark.y) <= mark.radius
        for i in np.flatnonzero(inside):
            seen[i].add(mark.feature)
    return [tuple(sorted(s)) for s in seen]


def place_features(poses, cell: float) -> list[tuple[str, ...]]:
    """Each scan's place: the square of side ``cell`` (m) of a grid over the plane that its pose is in.

    Examples
    --------
    >>> place_features([[0.2, 0.3, 0.0], [1.7, -0.2, 1.0]], 1.0)
    [('place 0,0',), ('place 1,-1',)]
    """
    if not cell > 0:
        raise ValueError(f"cell must be a positive length (m); got {cell!r}.")
    p = np.floor(finite_positions(poses) / cell).astype(np.int64)
    return [(f"{_PLACE}{i},{j}",) for i, j in p.tolist()]


def split_runs(time, *, gap: float | None = None, intervals=None) -> np.ndarray:
    """The run of each scan: a new run after each gap longer than ``gap`` s, or one per interval.

    With ``intervals`` (a list of ``(start, end)`` in s, in order, not
    overlapping), scans outside every interval get run -1.

    Examples
    --------
    >>> split_runs([0.0, 0.1, 5.0, 5.1, 20.0], gap=1.0).tolist()
    [0, 0, 1, 1, 2]
    >>> split_runs([0.0, 0.1, 5.0, 5.1, 20.0], intervals=[(0, 1), (4.5, 30)]).tolist()
    [0, 0, 1, 1, 1]
    """
    t = np.asarray(time, dtype=np.float64)
    if (gap is None) == (intervals is None):
        raise ValueError("Split by gap= (seconds) or by intervals= [(start, end), ...], one of the two.")
    if gap is not None:
        if not gap > 0:
            raise ValueError(f"gap must be a positive number of seconds; got {gap!r}.")
        return np.concatenate([[0], np.cumsum(np.diff(t) > gap)]).astype(np.int64)
    spans = [(float(a), float(b)) for a, b in intervals]
    if any(b < a for a, b in spans) or any(spans[k][1] > spans[k + 1][0] for k in range(len(spans) - 1)):
        raise ValueError(f"intervals must be (start, end) pairs in order, not overlapping; got {intervals!r}.")
    run = np.full(len(t), -1, dtype=np.int64)
    for k, (a, b) in enumerate(spans):
        run[(t >= a) & (t <= b)] = k
    return run


def visit_counts(poses, radius: float, leave: float | None = None) -> np.ndarray:
    """How many times the robot had been within ``radius`` of each scan's position before this visit.

    The robot enters the place of scan ``i`` (the disc of ``radius`` around
    its position) at an earlier scan within it that follows a moment beyond
    ``leave`` (default ``2 * radius``, so that hovering at the edge is not
    leaving) or that is the first within it. The count is the number of such
    entries before the current visit: 0 on the first visit. Its cost grows
    as the square of the number of scans (seconds for 10,000).

    Examples
    --------
    >>> x = [0.0, 1.0, 5.0, 1.0, 0.0, 5.0]          # out and back along a line
    >>> visit_counts(np.c_[x, np.zeros(6)], radius=1.5).tolist()
    [0, 0, 0, 1, 1, 1]
    """
    p = finite_positions(poses)
    if not radius > 0:
        raise ValueError(f"radius must be positive (m); got {radius!r}.")
    leave = 2 * radius if leave is None else leave
    if leave < radius:
        raise ValueError(f"leave ({leave}) must be at least radius ({radius}).")
    counts = np.zeros(len(p), dtype=np.int64)
    for i in range(len(p)):
        d = np.hypot(*(p[:i + 1] - p[i]).T)
        # the scans that are near (0) or far (1), in order; an entry is a near one first or after a far one
        events = np.where(d <= radius, 0, np.where(d > leave, 1, -1))
        events = events[events >= 0]
        entries = int(events[0] == 0) + int(np.sum((events[1:] == 0) & (events[:-1] == 1)))
        counts[i] = entries - 1    # scan i itself is near: the current visit is the last entry
    return counts


@takes_reading_options
def recording_task(paths, reading: Reading | None = None, *, marks=None, places: float | None = None,
                   gap: float | None = None, intervals=None, warmup: int = 1, name: str | None = None, seed: int = 0,
                   **options) -> Dataset:
    """An exploration task (and hold-out task) from recordings: runs, tracked features, poses.

    Parameters
    ----------
    paths : str, Path or sequence of them
        Recordings (CARMEN logs or bags), in the order they were driven
        (a str may list them comma-separated); each file is a run, split
        further by ``gap`` or ``intervals``.
    reading : Reading, optional
        How each recording is read (:class:`~novelty.io.recording.reading.Reading`):
        the scans' topic, poses, a bag's mounts (a laser mounted upside
        down whose bag holds no transform for it needs
        ``mounts="X,Y,YAW,flipped"``), the ring's sectors, the threshold.
        Its ``inputs="points"`` gives the ``points`` input of the detectors
        that read the robot's pose with each scan (the habituating maps:
        the pose, each sector's nearness and its end point in the world,
        :func:`novelty.io.scans.points.sweep_points`), read from the laser
        scans that have a pose. ``fragments``, ``mounts`` and ``echo``, given
        otherwise than by default, are kept in ``metadata["reading"]``.
    **options
        The options of :class:`~novelty.io.recording.reading.Reading` one by
        one, as a suite gives a task's options (``sectors=8``,
        ``pose_topic="/odom"``); over ``reading``'s.
    seed : int, default=0
        Unused: a recording is what it is (the benchmark gives every task a seed).
    marks : str, Path or sequence of Mark, optional
        Tracked features: a CSV file (:func:`read_marks`) or the marks.
    places : float, optional
        Track the places of a grid of this cell size (m) instead (or as well):
        the places the robot did not pass in the warm-up runs; those it
        passed there are the familiar ones (untracked), so the exploration
        scores compare a new place's scans with the familiar places'.
    gap, intervals
        How a file splits into runs (:func:`split_runs`); default one run a file.
    warmup : int, default=1
        The first runs, learned before anything is tracked.
    name : str, optional
        The task's name (default: the first file's).

    Returns
    -------
    Dataset
        As :func:`novelty.exploration.from_runs`, plus ``poses``,
        ``columns["time"]`` and ``metadata["sources"]``.
    """
    if reading is not None and not isinstance(reading, Reading):
        reading = reading_of("recording_task", reading, {})   # the old second argument: the topic
    reading = (reading or Reading()).replace(**options)
    if reading.threshold is None:
        raise ValueError("A recording task's rings are preprocessed: threshold must be a number of metres, "
                         "not None.")
    if isinstance(paths, str) and "," in paths and not Path(paths).exists():
        paths = paths.split(",")   # as the command line gives a list: paths=monday.bag,tuesday.bag
    paths = [paths] if isinstance(paths, (str, Path)) else list(paths)
    if marks is None and places is None:
        raise ValueError("Say what is tracked: marks= (a CSV of features) or places= (a grid cell in m).")
    if isinstance(marks, (str, Path)):
        marks = read_marks(marks)
    runs, features, envs, poses, times = [], [], [], [], []
    for path in paths:
        data = _points(path, reading) if reading.inputs == "points" else read_recording(path, reading)
        t = data.columns["time"]
        run = np.zeros(len(data), np.int64) if gap is None and intervals is None else \
            split_runs(t, gap=gap, intervals=intervals)
        seen = _features(data, marks, places)
        for r in np.unique(run[run >= 0]):
            take = np.flatnonzero(run == r)
            runs.append(data.X[take])
            features.append([seen[i] for i in take])
            envs.append(f"{Path(path).name}#{r}")
            poses.append(None if data.poses is None else data.poses[take])
            times.append(t[take])
    if places is not None:
        features = _new_places_only(features, warmup)
    task = from_runs(runs, features, warmup=warmup, name=name or Path(paths[0]).name, environments=envs)
    meta = dict(task.metadata, sources=[str(p) for p in paths], threshold_m=float(reading.threshold),
                encoding="1 - min(r, T) / T", description="Recorded runs of a robot.")
    given = reading_given(reading.fragments, reading.mounts, reading.echo)
    if given:
        meta["reading"] = given
    if reading.inputs == "points":
        meta.update(inputs="points", columns=points_columns(reading.sectors))
    pose_array = None if any(p is None for p in poses) else np.concatenate(poses)
    return replace(task, poses=pose_array, columns=dict(task.columns, time=np.concatenate(times)),
                   metadata=meta)


def _points(path, reading: Reading) -> Dataset:
    """A recording's laser scans that have a pose as the ``points`` input, with their times and poses."""
    sweeps = [s for s in read_sweeps(path, reading) if s.pose is not None]
    if not sweeps:
        raise ValueError(f"{path}: no scan with a pose; the points input places each echo in the world by the "
                         "robot's pose (give pose_topic=).")
    return Dataset(Path(path).name, sweep_points(sweeps, reading.sectors, reading.threshold),
                   poses=np.array([s.pose for s in sweeps], dtype=np.float64),
                   columns={"time": np.array([s.time for s in sweeps])})


def _new_places_only(features: list, warmup: int) -> list:
    """The runs' features without the places met in the warm-up runs (marked features kept)."""
    known = {f for run in features[:warmup] for seen in run for f in seen if f.startswith(_PLACE)}
    return [[tuple(f for f in seen if f not in known) for seen in run] for run in features]


def _features(data: Dataset, marks, places) -> list[tuple[str, ...]]:
    seen = [()] * len(data)
    if marks is not None:
        seen = mark_features(marks, data.columns["time"], data.poses)
    if places is not None:
        if data.poses is None:
            raise ValueError(f"places= needs poses; {data.name} has none (give pose_topic=).")
        seen = [tuple(sorted(set(a) | set(b))) for a, b in zip(seen, place_features(data.poses, places))]
    return seen
