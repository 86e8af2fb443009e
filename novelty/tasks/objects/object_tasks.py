"""Tasks from a recording with virtual objects: an inspection (hold-out) task and an exploration task.

Both read the recording once (:func:`novelty.io.read_sweeps`: its
scans as sweeps in the robot's base frame, mounts included), place the
objects (the user's, or drawn by a seed beside the path:
:mod:`.placement`), refuse those that cannot stand where they are put, cast
them into every sweep (:mod:`.raycast`) and label every scan with the object
it sees (:mod:`novelty.tasks.objects.casting`) and, with ``places=True``,
whether that object's place was seen before it appeared
(:mod:`novelty.tasks.objects.places`: the column ``seen_place``; each
object's ``seen_place`` and ``place_looks`` in the metadata). The rings are the paper's
(:func:`object_rings`: sectors reduced to their nearest echo, thresholded,
normalised, inverted), at one or several scales at once.

- :func:`inspection_task`: the robot learns the first part of the
  recording as it was (``learn``, a share of its scans); the objects appear
  after it. The test part is every later scan taken at a place the robot
  had learned (its pose within ``radius`` of a learned pose, facing within
  ``max_turn`` of it) or that sees an object, with the objects cast in;
  and, as a second run, the scans that see an object as they were recorded
  (the same place and moment without the object). ``y`` = 1 where a scan
  sees an object. The hold-out protocol scores them frozen.
- :func:`exploration_task`: every scan in order, learned as it comes; the
  objects appear after the warm-up and stay. A scan that sees an object
  counts for it, its exposure the robot's pass (:func:`.labels.passes`: 0
  at first sight). The runs are short stretches of the drive
  (``run_scans``), so that a first sight is compared with the familiar
  scans of the same stretch, not with other parts of the building.

A recording whose clock does not tell its scans apart (the Radish ``csail``
log writes six digits: two distinct times for 406 scans) is timed by the
scans' order, scan i at i s; objects given for it use that clock.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import replace
from pathlib import Path
from typing import Sequence

import numpy as np

from ...data import FAMILIAR, Dataset
from ...io.bags.read_report import ReadReport
from ...io.recording.readers import read_sweeps
from ...io.recording.reading import Reading, reading_given
from ...io.scans.points import points_columns, sweep_points
from ...io.scans.sweep_rings import RingMaker
from ...sonar.preprocessing import PAPER_THRESHOLD, preprocess
from ..exploration.runs import from_runs
from .casting import cast_all, passes, sightings
from .placement import check_objects, draw_objects, read_objects
from .places import PLACE_TOLERANCE, looks

__all__ = ["object_rings", "object_inputs", "INPUTS", "read_drive", "inspection_task", "exploration_task", "familiar_places",
           "LABEL_DEFAULTS"]

#: What counts as seeing an object: beams shortened by more than ``margin`` (m), at least ``min_beams``
#: of them, within the ring's threshold; a pass ends beyond ``leave`` (m).
LABEL_DEFAULTS = {"margin": 0.1, "min_beams": 3, "leave": 4.0}


#: What a scan's ``seen_place`` says (the metadata's ``labels``).
SEEN_PLACE = ("whether the place of the object this scan sees was seen before the object appeared: a beam of the "
              "scans learned before it passed through or ended within place_tolerance of its footprint "
              "(novelty.tasks.objects.places); False for a scan that sees no object")


def read_drive(path, topic=None, *, pose_topic=None, base_frame=None, mounts=None, fragments="auto",
               echo: str = "first", report: ReadReport | None = None) -> list:
    """The recording's sweeps that have a pose, timed by their order where the clock does not tell them apart.

    ``topic``, ``pose_topic``, ``base_frame``, ``mounts`` (where a bag's laser
    sits when the bag holds no transform for it: ``"X,Y,YAW[,flipped]"``, a
    laser mounted upside down included), ``fragments`` and ``echo`` are
    options of :class:`~novelty.io.recording.reading.Reading`, ``report``
    :func:`novelty.io.read_sweeps`'s. A laser whose
    place the bag does not give and no mount states is read as at the
    robot's centre, facing forward, upright, with a warning: objects cast
    into a laser read in the wrong place stand where the robot never saw
    them.
    """
    report = ReadReport() if report is None else report
    reading = Reading(topic=topic, pose_topic=pose_topic, base_frame=base_frame, mounts=mounts, fragments=fragments,
                      echo=echo)
    sweeps = [s for s in read_sweeps(path, reading, report=report) if s.pose is not None]
    for sensor, how in report.mounts.items():
        if "assumed" in how:
            warnings.warn(f"{path}: {sensor} {how}; an objects task takes the mount as mounts=\"X,Y,YAW[,flipped]\".",
                          UserWarning, stacklevel=2)
    if len(sweeps) < 2:
        raise ValueError(f"{path}: {len(sweeps)} scans with a pose; objects need a drive with poses "
                         "(give pose_topic=).")
    times = np.array([s.time for s in sweeps])
    if np.any(np.diff(times) <= 0):
        sweeps = [replace(s, time=float(i)) for i, s in enumerate(sweeps)]
    return sweeps


def object_rings(sweeps: Sequence, sectors=16, reduce="min", threshold: float = PAPER_THRESHOLD) -> np.ndarray:
    """Each sweep as the paper's input: one ring a scale in ``sectors``, side by side, preprocessed.

    Parameters
    ----------
    sweeps : sequence of Sweep
    sectors : int or sequence of int, default=16
        The number of sectors of each ring (several: several scales at once).
    reduce : {"min", "mean", "median"} or float, default="min"
        How a sector's beams become one range (:func:`novelty.io.scans.sectors.reduce_sectors`).
    threshold : float, default=4.0
        The paper's threshold (m): ``1 - min(r, T) / T``.
    """
    scales = [sectors] if isinstance(sectors, (int, np.integer)) else list(sectors)
    if not scales or any(isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1 for n in scales):
        raise ValueError(f"sectors must be an int >= 1 or a list of them; got {sectors!r}.")
    makers = [RingMaker(int(n), reduce) for n in scales]
    return np.array([np.concatenate([preprocess(make(s)[None], threshold)[0] for make in makers])
                     for s in sweeps])


#: What a task's rows are: the paper's ring, or the ``points`` input (:mod:`novelty.io.scans.points`).
INPUTS = ("ring", "points")


def object_inputs(sweeps: Sequence, inputs: str = "ring", sectors=16, reduce="min",
                  threshold: float = PAPER_THRESHOLD) -> np.ndarray:
    """The rows of a task: the rings (:func:`object_rings`) or the ``points`` input (pose, ring, end points).

    ``inputs="points"`` takes one number of ``sectors`` and the nearest echo
    (:func:`novelty.io.scans.points.sweep_points`); its ring columns are
    :func:`object_rings`'s.
    """
    if inputs not in INPUTS:
        raise ValueError(f"inputs must be one of {', '.join(map(repr, INPUTS))}; got {inputs!r}.")
    if inputs == "ring":
        return object_rings(sweeps, sectors, reduce, threshold)
    if reduce != "min":
        raise ValueError(f"The points input places each sector's nearest echo (reduce='min'); got reduce={reduce!r}.")
    return sweep_points(sweeps, sectors, threshold)


def familiar_places(poses, known, radius: float = 1.0, max_turn: float = math.pi / 2) -> np.ndarray:
    """Whether each pose is within ``radius`` (m) of a ``known`` pose, facing within ``max_turn`` (rad) of it.

    >>> familiar_places([[0.5, 0.0, 0.0], [0.5, 0.0, 3.0], [3.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]]).tolist()
    [True, False, False]
    """
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    k = np.asarray(known, dtype=np.float64).reshape(-1, 3)
    out = np.zeros(len(p), dtype=bool)
    for i in range(len(p)):
        near = np.hypot(k[:, 0] - p[i, 0], k[:, 1] - p[i, 1]) <= radius
        turn = np.abs((k[:, 2] - p[i, 2] + math.pi) % (2 * math.pi) - math.pi) <= max_turn
        out[i] = bool(np.any(near & turn))
    return out


def _objects(sweeps, objects, first: int, seed: int, n_objects: int, min_passes: int, before: int,
             threshold: float, unseen: bool = False) -> list:
    """The user's objects (checked) or ``n_objects`` drawn by ``seed`` to appear at scan ``first``."""
    start = float(sweeps[first].time)
    if objects is None:
        return draw_objects(sweeps, n_objects, seed, start=start, min_passes=min_passes, before=before,
                            leave=LABEL_DEFAULTS["leave"], margin=LABEL_DEFAULTS["margin"],
                            min_beams=LABEL_DEFAULTS["min_beams"], within=threshold, unseen=unseen,
                            tolerance=PLACE_TOLERANCE)
    if unseen:
        raise ValueError("unseen_places draws the objects; the objects given stand where they are given.")
    objects = read_objects(objects) if isinstance(objects, (str, Path)) else list(objects)
    early = [o.name for o in objects if o.start < start]
    if early:
        raise ValueError(f"Objects {early} appear before t={start:.2f} s, in the part the robot learns as it was "
                         f"(scans before {first}); give them a start at or after it, or learn less.")
    check_objects(objects, sweeps)
    return objects


def _seen_places(sweeps, objects, threshold: float, places: bool) -> np.ndarray | None:
    """How many of ``sweeps`` saw each object's place before it appeared (:func:`novelty.tasks.objects.places.looks`); None unless
    ``places``."""
    return looks(sweeps, objects, tolerance=PLACE_TOLERANCE, within=threshold) if places else None


def _place_labels(meta: dict, columns: dict, seen_place) -> None:
    """Add the column ``seen_place`` and what it says to a task labelled by places."""
    columns["seen_place"] = seen_place
    meta["labels"]["seen_place"] = SEEN_PLACE
    meta["labels"]["place_tolerance"] = PLACE_TOLERANCE


def _first_scan(n: int, learn: float) -> int:
    if not 0 < learn < 1:
        raise ValueError(f"learn must be a share of the scans in (0, 1); got {learn!r}.")
    return min(max(int(round(learn * n)), 1), n - 1)


def _cast(sweeps, objects, threshold: float):
    cast = cast_all(sweeps, objects, margin=LABEL_DEFAULTS["margin"], within=threshold)
    seen = sightings(cast.shortened, LABEL_DEFAULTS["min_beams"])
    if not seen.any():
        raise ValueError("No scan sees any of the objects: place them where the robot's laser reaches them.")
    # a scan that sees several objects counts for the one that changed most of its beams
    which = np.where(seen.any(axis=1), np.argmax(np.where(seen, cast.shortened, -1), axis=1), -1)
    return cast, seen, which


def _metadata(objects, sweeps, path, options: dict, reading: dict, report: ReadReport, looked=None) -> dict:
    # a ring task's metadata as it was before the points input existed: its rows keep their digest
    layout = {}
    if options.get("inputs", "ring") == "points":
        layout = {"inputs": "points", "columns": points_columns(int(options["sectors"]))}
    given = reading_given(reading["fragments"], reading["mounts"], reading["echo"])
    if given:
        layout["reading"] = given
    if report.lines():   # what reading a bag found and chose (a CARMEN log says nothing: its digest stays)
        layout["read"] = report.lines()
    places = [{} if looked is None else {"place_looks": int(n), "seen_place": bool(n > 0)}
              for n in (looked if looked is not None else [None] * len(objects))]
    return {**layout, "source": str(path), "objects": [{"kind": type(o).__name__.lower(), **{
        k: (float(v) if isinstance(v, (int, float)) else v) for k, v in vars(o).items()}, **place}
        for o, place in zip(objects, places)],
            "labels": {**LABEL_DEFAULTS, "within_m": options["threshold"]}, "sectors": options["sectors"],
            "reduce": options["reduce"], "threshold_m": float(options["threshold"]),
            "encoding": "1 - min(r, T) / T", "n_recorded_scans": len(sweeps)}


def inspection_task(path, objects=None, *, learn: float = 0.5, n_objects: int = 4, seed: int = 0,
                    min_passes: int = 1, places: bool = False, unseen_places: bool = False, inputs: str = "ring",
                    sectors=16, reduce="min",
                    threshold: float = PAPER_THRESHOLD,
                    radius: float = 1.0, max_turn: float = math.pi / 2, topic=None, pose_topic=None,
                    base_frame=None, mounts=None, fragments="auto", echo: str = "first",
                    name: str | None = None) -> Dataset:
    """A hold-out task: learn the recording's first part as it was, then find the objects (module docstring).

    Parameters
    ----------
    path : str or Path
        A recording with poses (:func:`novelty.io.read_sweeps`).
    objects : str, Path or sequence of objects, optional
        A CSV or TOML file of objects (:func:`.placement.read_objects`) or
        the objects; default ``n_objects`` drawn by ``seed``, seen at least
        once before they appear and ``min_passes`` times after.
    places : bool, default=False
        Label each object's place as seen or not while the robot learned
        (:mod:`novelty.tasks.objects.places`: the column ``seen_place``, each object's
        ``seen_place`` and ``place_looks`` in the metadata), for the
        benchmarks' scores on seen and unseen places apart.
    unseen_places : bool, default=False
        Draw the objects where no learned beam passed through or ended
        (:mod:`novelty.tasks.objects.places`): places the robot had never seen (implies ``places``).
    learn : float, default=0.5
        The share of the scans learned as recorded.
    inputs : {"ring", "points"}, default="ring"
        The rows: the paper's ring, or the ``points`` input (the pose, the
        ring and each sector's end point in the world: :func:`object_inputs`).
    sectors, reduce, threshold
        The rings (:func:`object_rings`).
    radius, max_turn
        Which later scans are at learned places (:func:`familiar_places`).
    topic, pose_topic, base_frame, mounts, fragments, echo
        Which of the recording's messages, and how a bag's scans are read
        (:func:`read_drive`): a laser mounted upside down whose bag holds no
        transform for it needs ``mounts="X,Y,YAW,flipped"``.
    """
    reading = dict(topic=topic, pose_topic=pose_topic, base_frame=base_frame, mounts=mounts, fragments=fragments,
                   echo=echo)
    report = ReadReport()
    sweeps = read_drive(path, **reading, report=report)
    first = _first_scan(len(sweeps), learn)
    objects = _objects(sweeps, objects, first, seed, n_objects, min_passes, 0 if unseen_places else 1, threshold,
                       unseen_places)
    cast, seen, which = _cast(sweeps, objects, threshold)
    places = places or unseen_places
    looked = _seen_places(sweeps[:first], objects, threshold, places)
    poses = cast.poses
    later = np.arange(len(sweeps)) >= first
    test = later & (familiar_places(poses, poses[:first], radius, max_turn) | (which >= 0))
    twins = later & (which >= 0)
    X = object_inputs(cast.sweeps, inputs, sectors, reduce, threshold)
    recorded = object_inputs(cast.recorded, inputs, sectors, reduce, threshold)
    take = np.r_[np.flatnonzero(~later), np.flatnonzero(test), np.flatnonzero(twins)]
    n_train, n_test, n_twin = int(first), int(test.sum()), int(twins.sum())
    seen_as = np.array([o.name for o in objects] + [FAMILIAR], dtype=object)[which]
    meta = _metadata(objects, sweeps, path, dict(inputs=inputs, sectors=sectors, reduce=reduce, threshold=threshold),
                     reading, report, looked)
    meta.update(task=name or f"inspection-objects-{Path(path).name}", train_passes=1,
                description="A recording learned as it was; virtual objects appear in its later part.",
                test_parts={"with objects": n_test, "as recorded (the scans that see an object)": n_twin},
                familiar_places={"radius_m": float(radius), "max_turn_rad": float(max_turn)})
    columns = {"time": cast.times[take], "scan": take,
               "object": np.r_[seen_as[~later], seen_as[test], seen_as[twins]].astype(str),
               "with_objects": np.r_[np.ones(n_train + n_test), np.zeros(n_twin)].astype(bool)}
    if places:
        seen_place = np.r_[looked > 0, False][which]
        _place_labels(meta, columns, np.r_[seen_place[~later], seen_place[test], seen_place[twins]])
    return Dataset(
        meta["task"], np.r_[X[~later], X[test], recorded[twins]],
        y=np.r_[np.zeros(n_train), (which[test] >= 0), np.zeros(n_twin)].astype(np.int64),
        split=np.array(["train"] * n_train + ["test"] * (n_test + n_twin)),
        poses=poses[take], run=np.r_[np.zeros(n_train + n_test), np.ones(n_twin)].astype(np.int64),
        columns=columns, metadata=meta)


def exploration_task(path, objects=None, *, warmup: float = 0.3, run_scans: int = 20, n_objects: int = 4,
                     seed: int = 0, min_passes: int = 3, seen_before: int = 0, places: bool = False,
                     unseen_places: bool = False,
                     inputs: str = "ring", sectors=16,
                     reduce="min", threshold: float = PAPER_THRESHOLD, topic=None, pose_topic=None, base_frame=None,
                     mounts=None, fragments="auto", echo: str = "first", name: str | None = None) -> Dataset:
    """An exploration task: the objects appear after the warm-up and stay; exposures are passes (module docstring).

    Parameters
    ----------
    path, objects, seed, n_objects, inputs, sectors, reduce, threshold, topic, pose_topic, base_frame, mounts, fragments, echo
        As :func:`inspection_task`; drawn objects are passed ``min_passes``
        times after they appear.
    seen_before : int, default=0
        Drawn objects stand where the robot looked at least this many times
        before they appear (0: anywhere beside its later path, a place it may
        meet for the first time with the object in it).
    places : bool, default=False
        Label each object's place as seen or not before it appeared (as
        :func:`inspection_task`).
    unseen_places : bool, default=False
        Draw the objects where no beam before they appear passed through or
        ended (:mod:`novelty.tasks.objects.places`): places the robot had never seen (``seen_before``
        0; implies ``places``).
    warmup : float, default=0.3
        The share of the scans (whole runs) before the objects appear.
    run_scans : int, default=20
        Scans a run: a stretch of the drive whose familiar scans a first sight is compared with.
    """
    if isinstance(run_scans, bool) or not isinstance(run_scans, (int, np.integer)) or run_scans < 1:
        raise ValueError(f"run_scans must be an int >= 1; got {run_scans!r}.")
    reading = dict(topic=topic, pose_topic=pose_topic, base_frame=base_frame, mounts=mounts, fragments=fragments,
                   echo=echo)
    report = ReadReport()
    sweeps = read_drive(path, **reading, report=report)
    n_runs = len(sweeps) // run_scans
    if n_runs < 2:
        raise ValueError(f"{path}: {len(sweeps)} scans make {n_runs} run(s) of {run_scans}; use shorter runs.")
    warm = min(max(int(round(warmup * n_runs)), 1), n_runs - 1)
    objects = _objects(sweeps, objects, warm * run_scans, seed, n_objects, min_passes, seen_before, threshold,
                       unseen_places)
    cast, seen, which = _cast(sweeps, objects, threshold)
    places = places or unseen_places
    looked = _seen_places(sweeps, objects, threshold, places)
    poses, times = cast.poses, cast.times
    exposure = np.full(len(sweeps), -1, dtype=np.int64)
    for k, obj in enumerate(objects):
        mine = which == k
        exposure[mine] = passes(seen[:, k], poses, obj, LABEL_DEFAULTS["leave"])[mine]
    run = np.minimum(np.arange(len(sweeps)) // run_scans, n_runs - 1)
    cuts = np.flatnonzero(np.diff(run)) + 1
    names = np.array([o.name for o in objects] + [FAMILIAR], dtype=object)[which]
    X = object_inputs(cast.sweeps, inputs, sectors, reduce, threshold)
    label = name or f"exploration-objects-{Path(path).name}"
    task = from_runs(np.split(X, cuts), np.split(names, cuts), warmup=warm, name=label,
                     environments=[f"{Path(path).name}#{r}" for r in range(n_runs)])
    meta = dict(task.metadata, **_metadata(objects, sweeps, path, dict(inputs=inputs, sectors=sectors, reduce=reduce,
                                                                         threshold=threshold), reading, report,
                                               looked))
    meta.update(task=label, run_scans=int(run_scans),
                description="A recording driven on; virtual objects appear after the warm-up and stay.")
    meta["labels"]["exposure"] = "the robot's passes of the object before this one (0 at first sight)"
    columns = dict(task.columns, exposure=exposure, time=times,
                   object=np.where(which >= 0, names, FAMILIAR).astype(str))
    if places:
        _place_labels(meta, columns, np.r_[looked > 0, False][which])
    return replace(task, y=((exposure == 0) & (which >= 0)).astype(np.int64), poses=poses, metadata=meta,
                   columns=columns)
