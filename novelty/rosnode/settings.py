"""The node's private parameters: their names, defaults and checks, without rospy.

A ROS user sets them as any node's (``rosparam load``, a launch file's
``<rosparam>``, ``_sectors:=16`` on the command line); :meth:`Settings.read`
takes them as a dict (what ``rospy.get_param("~")`` returns) and checks each
in the project's message form, naming the parameter as ROS does::

    The '~sectors' parameter of the novelty node must be an int in [1, inf). Got 0 instead.

The reading options are those of ``novelty run`` on a recording (its
``--topic``, ``--pose-topic``, ``--base-frame``, ``--mount``, ``--fragments``,
``--echo``, ``--tolerance``, ``--sectors``, ``--reduce``, ``--limits``,
``--front``, ``--stamps``, ``--range-threshold``, ``--param``, ``--alarm``),
so that a bag played into the node reads as ``novelty run`` reads the bag.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field, fields
from typing import Any, Mapping

from .._validation import Bounds, Interval, Options
from ..alarms import parse_alarm
from ..io.frames.mounts import parse_mount
from ..io.ros.decoders import ECHOES
from ..io.scans.sectors import REDUCTIONS
from ..sonar.preprocessing import PAPER_THRESHOLD

__all__ = ["Settings", "SettingsError", "PARAMETERS"]


class SettingsError(ValueError):
    """A parameter of the node out of its range, of the wrong type, or unknown."""


_TEXT = (str,)
_POSITIVE = Interval(numbers.Real, 0, None, closed="neither")


@dataclass(frozen=True)
class Settings:
    """The node's parameters, checked (see the module docstring and ``docs/guide/live-robot.md``).

    Attributes
    ----------
    detector : str
        A registered detector's name (``novelty list detectors``); or
    model : str
        A saved model (``.npz``) to load at start and continue learning from; given, ``detector`` and
        ``params`` are not used (:attr:`unused`).
    params : dict
        The detector's parameters (``novelty run --param``).
    save : str
        Where the model is saved, atomically: on shutdown and by the ``~save`` service ("" none).
    scan_topics : list of str
        The scans' topics (LaserScan, MultiEchoLaserScan, PointCloud2 or sonars' Range); empty: the node's
        relative topic ``scan`` (remap it: ``scan:=/front/scan``). Several lasers are merged into one scan,
        several Range topics are one sonar each, as ``novelty run --topic a,b`` reads them.
    pose_topic : str
        Poses from an Odometry or PoseStamped topic instead of tf ("" tf).
    base_frame, fixed_frame : str
        The robot's frame (default ``base_link``, else ``base_footprint``: REP 105) and the frame its
        poses are looked up in (default the root of the base frame's tree: ``map`` or ``odom``).
    mounts : list of str
        ``[TOPIC=]X,Y,YAW[,flipped]`` for a sensor tf does not place (``novelty run --mount``).
    fragments : "auto" or int
    echo : {"first", "last", "strongest"}
    tolerance : float
        Seconds within which several lasers' scans are merged.
    sectors : int or None
        Sectors of a ring (default 16) or of the points input (default 180, or one a beam).
    reduce : {"min", "mean", "median"} or float
    limits : (float, float) or None
        Degrees from the front.
    front : float
        Degrees.
    range_threshold : float
        The paper's preprocessing threshold T (m).
    stamps : bool
        Give the detector the scans' times as elapsed time.
    threshold : float or None
        The detector's novelty threshold (``--param threshold=``), None for its own.
    alarm : str
        The alarm policy (``novelty.alarms.parse_alarm``'s forms).
    learning : bool
        Learn from the start (False: start frozen; the ``~set_learning`` service switches).
    transform_timeout : float
        Seconds a scan waits for its transforms (its pose, its mount) before it is read without them.
    queue_size : int
        Scans waiting to be scored beyond which the oldest is dropped (and counted).
    stopped_after : float
        Seconds without a scan after which the diagnostics say the scans stopped.
    """

    detector: str = ""
    model: str = ""
    params: dict = field(default_factory=dict)
    save: str = ""
    scan_topics: tuple = ()
    pose_topic: str = ""
    base_frame: str = ""
    fixed_frame: str = ""
    mounts: tuple = ()
    fragments: Any = "auto"
    echo: str = "first"
    tolerance: float = 0.1
    sectors: int | None = None
    reduce: Any = "min"
    limits: tuple | None = None
    front: float = 0.0
    range_threshold: float = PAPER_THRESHOLD
    stamps: bool = False
    threshold: float | None = None
    alarm: str = "threshold"
    learning: bool = True
    transform_timeout: float = 1.0
    queue_size: int = 10
    stopped_after: float = 2.0

    @classmethod
    def read(cls, given: Mapping[str, Any]) -> "Settings":
        """The settings from the node's private parameters (``rospy.get_param("~")``), checked."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(given) - known)
        if unknown:
            raise SettingsError(f"Unknown parameter{'s' * (len(unknown) > 1)} "
                                f"{', '.join('~' + u for u in unknown)} of the novelty node; its parameters: "
                                f"{', '.join('~' + k for k in PARAMETERS)}.")
        values = {}
        for name in PARAMETERS:
            if name in given:
                values[name] = _checked(name, given[name])
        settings = cls(**values)
        settings._check_together()
        return settings

    def _check_together(self) -> None:
        if not self.detector and not self.model:
            raise SettingsError("Give the novelty node ~detector (a registered name: novelty list detectors) or "
                                "~model (a saved model to continue from).")
        if self.threshold is not None:
            try:
                parse_alarm(self.alarm, self.threshold)
            except ValueError as exc:
                raise SettingsError(f"~alarm: {exc}") from None

    @property
    def unused(self) -> list[str]:
        """The parameters a loaded ``~model`` makes unused (a node started again keeps the master's parameters)."""
        return [f"~{name}" for name in ("detector", "params") if self.model and getattr(self, name)]

    @property
    def limits_radians(self) -> tuple[float, float] | None:
        return None if self.limits is None else tuple(math.radians(v) for v in self.limits)


def _text(name: str, value) -> str:
    if not isinstance(value, str):
        raise _error(name, "a string", value)
    return value.strip()


def _topics(name: str, value) -> tuple:
    """A list of names, or one text of names separated by commas or spaces (as ROS launch files write them)."""
    if isinstance(value, str):
        value = value.replace(",", " ").split()
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) and v.strip() for v in value):
        raise _error(name, "a list of names (or one text of names separated by commas)", value)
    return tuple(v.strip() for v in value)


def _mounts(name: str, value) -> tuple:
    if isinstance(value, Mapping):   # {topic: "X,Y,YAW[,flipped]"}
        value = [f"{topic}={mount}" for topic, mount in value.items()]
    elif isinstance(value, str):
        value = [value] if value.strip() else []
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        raise _error(name, "a list of [TOPIC=]X,Y,YAW[,flipped] (m, m, degrees)", value)
    for text in value:
        try:
            parse_mount(text)
        except ValueError as exc:
            raise SettingsError(f"~{name}: {exc}") from None
    return tuple(value)


def _fragments(name: str, value):
    if value == "auto" or Interval(numbers.Integral, 1, None).accepts(value):
        return value
    raise _error(name, "'auto' or an int in [1, inf)", value)


def _reduce(name: str, value):
    if value in REDUCTIONS or Interval(numbers.Real, 0, 100).accepts(value):
        return value
    raise _error(name, f"one of {', '.join(REDUCTIONS)} or a percentile in [0, 100]", value)


def _limits(name: str, value):
    if value is None or value == "":
        return None
    if isinstance(value, str):   # "-90,90", as novelty run --limits takes it
        try:
            value = [float(v) for v in value.split(",")]
        except ValueError:
            raise _error(name, "LOW,HIGH in degrees", value) from None
    if not Bounds().accepts(value) or not all(-360 <= v <= 360 for v in value):
        raise _error(name, "a pair [LOW, HIGH] of degrees in [-360, 360] with LOW < HIGH", value)
    return tuple(float(v) for v in value)


def _params(name: str, value) -> dict:
    if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
        raise _error(name, "a mapping of the detector's parameters (YAML: {n_rows: 5, alpha: 1.2})", value)
    return dict(value)


def _alarm(name: str, value) -> str:
    value = _text(name, value)
    try:
        parse_alarm(value, 0.5)   # the form only; its threshold is the detector's
    except ValueError as exc:
        raise SettingsError(f"~{name}: {exc}") from None
    return value


def _rule(rule, allow_none: bool = False):
    def check(name, value):
        if value is None and allow_none:
            return None
        if not rule.accepts(value):
            raise _error(name, rule.describe(), value)
        return float(value) if isinstance(rule, Interval) and rule.kind is numbers.Real else value
    return check


def _flag(name: str, value) -> bool:
    if not isinstance(value, bool):
        raise _error(name, "true or false", value)
    return value


#: Each parameter's check, in the order the guide lists them.
PARAMETERS = {
    "detector": _text, "model": _text, "params": _params, "save": _text,
    "scan_topics": _topics, "pose_topic": _text, "base_frame": _text, "fixed_frame": _text, "mounts": _mounts,
    "fragments": _fragments, "echo": _rule(Options(ECHOES)), "tolerance": _rule(Interval(numbers.Real, 0, None)),
    "sectors": _rule(Interval(numbers.Integral, 1, None), allow_none=True), "reduce": _reduce, "limits": _limits,
    "front": _rule(Interval(numbers.Real, -360, 360)), "range_threshold": _rule(_POSITIVE), "stamps": _flag,
    "threshold": _rule(Interval(numbers.Real, None, None), allow_none=True), "alarm": _alarm, "learning": _flag,
    "transform_timeout": _rule(_POSITIVE), "queue_size": _rule(Interval(numbers.Integral, 1, None)),
    "stopped_after": _rule(_POSITIVE),
}


def _checked(name: str, value):
    value = PARAMETERS[name](name, value)
    return value


def _error(name: str, expected: str, value) -> SettingsError:
    return SettingsError(f"The '~{name}' parameter of the novelty node must be {expected}. Got {value!r} instead.")
