"""The node's parts built from its parameters, without rospy: the detector, the alarm, the reading, the scorer.

As ``novelty run`` builds them for a recording: the detector from the
registry (``~detector`` with ``~params``, checked as a benchmark checks it)
or a saved model (``~model``); the alarm policy ``~alarm`` with the
detector's threshold (or ``~threshold``); the points input for a detector
that reads the robot's pose with each scan (``input_layout == "points"``),
else the paper's ring. Anything that stops the node from starting is a
:class:`StartError`, whose message is the one line the command prints.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from .. import load
from ..alarms import parse_alarm
from ..bench.spec_checks import check_detector
from ..bench.specs import DetectorSpec, SuiteError
from ..persistence import ModelFileError
from ..registry import RegistryError
from ..io.recording.reading import Reading
from ..io.ros.messages import LaserScan, Pose
from ..io.scans.points import POINTS_SECTORS
from .reading import LiveReading
from .scoring import LiveScorer
from .settings import Settings, SettingsError

__all__ = ["build", "StartError", "make_detector", "make_reading", "reading_options", "alarm_policy", "warm_up"]


class StartError(Exception):
    """What keeps the node from starting: one line for the user, and a non-zero exit."""


def build(params: Mapping, resolve: Callable[[str], str] = lambda name: name,
          where: str = "novelty node") -> tuple[LiveScorer, Settings, list[str]]:
    """The scorer, the settings and the topics to follow, from the node's private parameters.

    ``resolve`` turns a topic's name into the one the node subscribes to
    (``rospy.resolve_name``: the node's namespace, remappings).
    """
    try:
        settings = Settings.read(params)
    except SettingsError as exc:
        raise StartError(str(exc)) from None
    fresh = make_detector(settings)
    detector = fresh()
    alarm = alarm_policy(detector, settings)
    inputs = "points" if getattr(detector, "input_layout", None) == "points" else "ring"
    reading = make_reading(settings, inputs, resolve, where)
    scorer = LiveScorer(detector, reading, alarm, fresh, stamps=settings.stamps, learning=settings.learning)
    return scorer, settings, reading.topics


def reading_options(settings: Settings, inputs: str, resolve: Callable[[str], str] = lambda name: name) -> Reading:
    """The :class:`~novelty.io.recording.reading.Reading` of the node's parameters, as ``novelty run``'s options
    make one for a recording: topics resolved, degrees in radians, the points input's sectors 180 unless given."""
    topics = [resolve(t) for t in settings.scan_topics or ("scan",)]
    sectors = settings.sectors or (POINTS_SECTORS if inputs == "points" else 16)
    try:
        return Reading(topic=topics if len(topics) > 1 else topics[0],
                       pose_topic=resolve(settings.pose_topic) if settings.pose_topic else None,
                       base_frame=settings.base_frame or None,
                       mounts=[_resolved_mount(m, resolve) for m in settings.mounts] or None,
                       fragments=settings.fragments, echo=settings.echo, tolerance=settings.tolerance, sectors=sectors,
                       reduce=settings.reduce, limits=settings.limits_radians, front=math.radians(settings.front),
                       threshold=settings.range_threshold, inputs=inputs, stamps=settings.stamps)
    except ValueError as exc:
        if inputs == "points" and "apply to the ring only" in str(exc):
            raise StartError("The points input reads each sector's nearest echo over the whole scan, placed in the "
                             "world by the robot's pose: no ~reduce, ~limits or ~front.") from None
        raise StartError(str(exc)) from None


def make_reading(settings: Settings, inputs: str, resolve: Callable[[str], str] = lambda name: name,
                 where: str = "novelty node") -> LiveReading:
    """The live reading the node's parameters say."""
    return LiveReading(reading_options(settings, inputs, resolve), fixed_frame=settings.fixed_frame or None,
                       one_a_beam=settings.sectors is None, timeout=settings.transform_timeout, where=where)


def warm_up(scorer: LiveScorer, settings: Settings) -> None:
    """Compile what the first scans will run, before any arrives: a made-up scan through copies of the parts.

    The compiled kernels (numba's: the readers', the detector's) are compiled
    at their first call, seconds on a first run; a node that compiled them at
    its first scan would drop the scans that came meanwhile. The copies are
    thrown away; the scorer is untouched. Whatever a made-up scan cannot go
    through (a model of another number of sectors) is left to the first real one.
    """
    beams = 360
    options = scorer.reading.reading.replace(topic="/warm_up", pose_topic="/warm_up_pose", mounts="0.1,0,0",
                                             fragments=1)
    reading = LiveReading(options, one_a_beam=scorer.reading.sectors is None, where="warm-up")
    ranges = np.where(np.arange(beams) % 9 == 0, np.inf, 1.0 + 0.01 * np.arange(beams))
    scan = LaserScan(1.0, ranges, -math.pi, 2 * math.pi / beams, 0.05, 30.0, frame="warm_up")
    rows = reading.push("/warm_up_pose", Pose(0.0, 0.0, 0.0, 0.0), 0.0)
    rows += reading.push("/warm_up", scan, 0.0) + reading.push("/warm_up_pose", Pose(2.0, 0.1, 0.0, 0.1), 0.0)
    rows += reading.flush()
    detector = scorer.fresh()
    try:
        for i, row in enumerate(rows * 2):
            detector.score_learn_one(row.x, float(i) if settings.stamps else None)
            detector.score_one(row.x)
            if hasattr(detector, "cell_novelty"):
                detector.cell_novelty(row.x)
    except ValueError:   # a loaded model of another input: its first real scan compiles the rest
        pass


def make_detector(settings: Settings) -> Callable[[], object]:
    """A function that builds the detector at start (and again for a reset): a new one, or the model loaded."""
    if settings.model:
        path = Path(settings.model).expanduser()
        if not path.is_file():
            raise StartError(f"~model: no such file: {settings.model}")
        try:
            load(path)
        except (ModelFileError, OSError, ValueError) as exc:
            raise StartError(f"~model {settings.model} could not be loaded: {exc}") from None
        return lambda: _with_threshold(load(path), settings.threshold)
    params = dict(settings.params)
    if settings.threshold is not None:
        params["threshold"] = settings.threshold
    try:
        detector = check_detector(DetectorSpec(settings.detector, params))
    except (SuiteError, RegistryError) as exc:
        raise StartError(f"~detector: {exc}") from None
    if not getattr(detector, "supports_online", True):
        raise StartError(f"~detector: {settings.detector} learns in batch only; it cannot learn live scans.")
    return lambda: check_detector(DetectorSpec(settings.detector, params))


def _with_threshold(detector, threshold: float | None):
    if threshold is not None:
        detector.set_params(threshold=threshold)
    return detector


def alarm_policy(detector, settings: Settings):
    """The ``~alarm`` policy, its threshold the detector's; None for a detector without a threshold."""
    threshold = getattr(detector, "threshold", None)
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float)):
        threshold = None
    try:
        return parse_alarm(settings.alarm, threshold) if threshold is not None or settings.alarm != "threshold" \
            else None
    except ValueError as exc:
        raise StartError(f"~alarm: {exc}") from None


def _resolved_mount(text: str, resolve) -> str:
    topic, sep, values = text.rpartition("=")
    return f"{resolve(topic)}={values}" if sep and topic else text
