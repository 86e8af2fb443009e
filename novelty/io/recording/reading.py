"""How a recording is read: one frozen set of options, :class:`Reading`, checked once.

Every way into a recording takes the same options: the readers
(:func:`novelty.io.read_rings`, :func:`~novelty.io.read_sweeps`,
:func:`~novelty.io.read_recording`), the task of a user's recordings
(``recording``, :func:`novelty.tasks.recordings.recording_task`), ``novelty
run --data run.bag`` (:mod:`novelty.cli.recording` builds one from the
command line) and a live node (from its parameters,
:meth:`Reading.from_mapping`). A :class:`Reading` says which messages are
the scans and where the poses come from, how a bag's scans become whole
sweeps in the robot's base frame, how a sweep becomes the paper's ring (or
the ``points`` input), and the paper's preprocessing threshold. Its values
are checked when it is made, with the project's message form::

    The 'echo' parameter of Reading must be one of 'first', 'last', 'strongest'. Got 'both' instead.

:meth:`Reading.to_mapping` gives it back as plain data (a task's metadata,
a log); :meth:`Reading.from_mapping` makes one of such data, refusing a key
it does not know with the list of those it does.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import numbers
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from ..._validation import Instance, Interval, Options, unknown_parameters, validate_parameters
from ...sonar.preprocessing import PAPER_THRESHOLD
from ..frames.mounts import Mount, parse_mount
from ..ros.decoders import ECHOES
from ..scans.sectors import REDUCTIONS

__all__ = ["Reading", "INPUTS", "RING_ONLY", "mount_options", "reading_given", "reading_of", "takes_reading_options"]

#: What a scan becomes: the paper's ring, or the ``points`` input (:mod:`novelty.io.scans.points`).
INPUTS = ("ring", "points")
_STR = Instance((str,), "a str")


@dataclass(frozen=True)
class Reading:
    """How a recording is read (see the module docstring).

    Parameters
    ----------
    topic : str or sequence of str, optional
        The scans: a CARMEN message (``FLASER`` by default, ``RLASER``,
        ``ROBOTLASER1``), or a bag's ``LaserScan``, ``MultiEchoLaserScan``,
        ``PointCloud2`` or ``Range`` topic (default: its only one); several
        topics are several lasers merged into one sweep, or one ``Range``
        topic a sonar. Kept as a str or a tuple.
    pose_topic : str, optional
        Where poses come from: a CARMEN log's own corrected poses (None) or
        ``ODOM``; a bag's ``Odometry``, ``PoseStamped`` or ``tf`` topic
        (default: ``/tf`` where it holds a moving chain to the base frame),
        interpolated at each scan's time.
    base_frame : str, optional
        The robot's frame in a bag's tf tree (default: REP 105's
        ``base_link``, else ``base_footprint``).
    mounts : str, Mount, sequence or dict of them, optional
        Where a bag's sensor sits when the bag holds no transform for it (or
        to override the bag's): ``"[TOPIC=]X,Y,YAW[,flipped]"`` (m, m,
        degrees) or a :class:`~novelty.io.frames.mounts.Mount`; a dict maps
        topics to mounts, one without a topic is every topic's. Kept as a
        tuple: each text as given, each mount as a pair ``(topic or None,
        Mount)``.
    fragments : "auto" or int, default="auto"
        Messages a revolution of a scanner that splits them
        (:mod:`novelty.io.scans.assembly`): detected, or stated; 1 turns
        assembly off.
    echo : {"first", "last", "strongest"}, default="first"
        The echo of a ``MultiEchoLaserScan``'s beams read.
    tolerance : float, default=0.1
        Seconds within which several sensors' sweeps are merged into one.
    fov : float, default=pi
        The field of view (rad) of CARMEN's ``FLASER`` and ``RLASER``, which
        do not state it.
    sensors : sequence of str, or dict of str to float, optional
        The sonars of a ring in order, or each sonar's mounting angle (rad)
        (default: their angles from the tf tree, else their names in
        natural order; :func:`novelty.io.scans.sonar_rings.sonar_rings`).
    max_span : float, optional
        The longest time (s) a sonar ring's readings span.
    sectors : int, default=16
        The ring's sectors (the paper's 16 sonars), or the ``points``
        input's.
    reduce : {"min", "mean", "median"} or float, default="min"
        How a sector's beams become one range (a number ``q``: the q-th
        percentile; :func:`novelty.io.scans.sectors.reduce_sectors`).
    limits : (float, float), optional
        The span cut into sectors (rad from the front; default the whole scan).
    front : float, default=0.0
        The angle (rad) of the robot's front in the scans' frame.
    clip : float, optional
        Ranges beyond ``clip`` (m) count as ``clip`` before reducing.
    threshold : float or None, default=4.0
        The paper's preprocessing threshold ``T`` (m), ``1 - min(r, T) / T``;
        None keeps the ranges in metres (:func:`novelty.io.read_recording`).
    inputs : {"ring", "points"}, default="ring"
        What a scan becomes: the paper's ring, or the ``points`` input (the
        pose, each sector's nearness and its end point in the world:
        :mod:`novelty.io.scans.points`), which reads each sector's nearest
        echo over the whole scan, so the ring's own options (``reduce``,
        ``limits``, ``front``, ``clip``, ``sensors``, ``max_span``) are
        refused with it.
    stamps : bool, default=False
        Give a detector the messages' times as elapsed time (default: one
        step a scan, as the paper presents one perception a step).

    Examples
    --------
    >>> reading = Reading(topic="/scan", pose_topic="/odom", sectors=8, mounts="/scan=0.2,0,0")
    >>> reading.sectors, reading.mounts
    (8, ('/scan=0.2,0,0',))
    >>> Reading.from_mapping(reading.to_mapping()) == reading
    True
    >>> Reading(echo="both")
    Traceback (most recent call last):
    ...
    ValueError: The 'echo' parameter of Reading must be one of 'first', 'last', 'strongest'. Got 'both' instead.
    """

    topic: str | tuple[str, ...] | None = None
    pose_topic: str | None = None
    base_frame: str | None = None
    mounts: tuple | None = None
    fragments: str | int = "auto"
    echo: str = "first"
    tolerance: float = 0.1
    fov: float = math.pi
    sensors: tuple | None = None
    max_span: float | None = None
    sectors: int = 16
    reduce: str | float = "min"
    limits: tuple[float, float] | None = None
    front: float = 0.0
    clip: float | None = None
    threshold: float | None = PAPER_THRESHOLD
    inputs: str = "ring"
    stamps: bool = False

    _parameter_rules = {
        "topic": (_STR, Instance((tuple,), "a sequence of topics"), Options((None,))),
        "pose_topic": (_STR, Options((None,))),
        "base_frame": (_STR, Options((None,))),
        "fragments": (Options(("auto",)), Interval(numbers.Integral, 1, None)),
        "echo": Options(ECHOES),
        "tolerance": Interval(numbers.Real, 0, None),
        "fov": Interval(numbers.Real, 0, 2 * math.pi, closed="right"),
        "max_span": Interval(numbers.Real, 0, None, closed="neither", allow_none=True),
        "sectors": Interval(numbers.Integral, 1, None),
        "reduce": (Options(REDUCTIONS), Interval(numbers.Real, 0, 100)),
        "front": Interval(numbers.Real),
        "clip": Interval(numbers.Real, 0, None, closed="neither", allow_none=True),
        "threshold": Interval(numbers.Real, 0, None, closed="neither", allow_none=True),
        "inputs": Options(INPUTS),
        "stamps": Options((True, False)),
    }

    def __post_init__(self):
        normal = {"topic": _topics(self.topic), "mounts": _mounts(self.mounts), "sensors": _sensors(self.sensors),
                  "limits": _limits(self.limits)}
        for name, value in normal.items():
            object.__setattr__(self, name, value)
        validate_parameters(self)
        if self.inputs == "points":
            ring_only = sorted(k for k, default in RING_ONLY.items() if getattr(self, k) != default)
            if ring_only:
                raise ValueError(f"The points input of Reading reads each sector's nearest echo over the whole "
                                 f"scan; {', '.join(ring_only)} apply to the ring only.")

    # ------------------------------------------------------------------ as data
    @classmethod
    def fields(cls) -> tuple[str, ...]:
        """The options' names, in order."""
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def from_mapping(cls, mapping: Mapping[str, Any]) -> "Reading":
        """A reading of the options in ``mapping`` (a suite's task options, a node's parameters, :meth:`to_mapping`).

        A key that is not an option is refused, naming the options.
        """
        _check_names(mapping)
        return cls(**mapping)

    def to_mapping(self) -> dict[str, Any]:
        """Every option as plain data (lists, dicts, text, numbers), as :meth:`from_mapping` takes it back.

        A mount given as a :class:`~novelty.io.frames.mounts.Mount` (not as
        text) is written as its description, which is not read back.
        """
        out = {name: getattr(self, name) for name in self.fields()}
        if isinstance(self.topic, tuple):
            out["topic"] = list(self.topic)
        if self.mounts is not None:
            out["mounts"] = [m if isinstance(m, str) else (f"{m[0]}: " if m[0] else "") + m[1].describe()
                             for m in self.mounts]
        if self.sensors is not None:
            out["sensors"] = dict(self.sensors) if _by_angle(self.sensors) else list(self.sensors)
        if self.limits is not None:
            out["limits"] = list(self.limits)
        return out

    def replace(self, **changes) -> "Reading":
        """This reading with ``changes`` (options by name; an unknown one refused, naming the options)."""
        _check_names(changes)
        return dataclasses.replace(self, **changes)

    # --------------------------------------------------------- as the layers take it
    @property
    def topics(self) -> str | list[str] | None:
        """The scans' topic(s) as the readers take them: a str, a list, or None."""
        return list(self.topic) if isinstance(self.topic, tuple) else self.topic

    @property
    def sonar_order(self):
        """``sensors`` as :func:`~novelty.io.scans.sonar_rings.sonar_rings` takes it: names, a dict, or None."""
        if self.sensors is None:
            return None
        return dict(self.sensors) if _by_angle(self.sensors) else list(self.sensors)

    def mount_map(self) -> dict:
        """The mounts as a dict of topic (None: every topic) to :class:`~novelty.io.frames.mounts.Mount`."""
        return mount_options(self.mounts)


#: the options of the ring that the points input does not read, and their defaults
RING_ONLY = {"reduce": "min", "limits": None, "front": 0.0, "clip": None, "sensors": None, "max_span": None}


def _check_names(given: Mapping) -> None:
    message = unknown_parameters("Reading", given, list(Reading.fields()))
    if message is not None:
        raise ValueError(message)


def _refuse(name: str, expected: str, value) -> ValueError:
    return ValueError(f"The '{name}' parameter of Reading must be {expected}. Got {value!r} instead.")


def _topics(topic):
    if topic is None or isinstance(topic, str):
        return topic
    if isinstance(topic, (list, tuple)) and topic and all(isinstance(t, str) and t for t in topic):
        return tuple(topic)
    raise _refuse("topic", "a str, a non-empty sequence of str or None", topic)


def _mounts(mounts) -> tuple | None:
    """Each mount as its text (checked: :func:`~novelty.io.frames.mounts.parse_mount`) or ``(topic, Mount)``."""
    if mounts is None:
        return None
    if isinstance(mounts, (str, Mount)):
        mounts = [mounts]
    if isinstance(mounts, Mapping):
        mounts = [_for_topic(topic, m) for topic, m in mounts.items()]
    out = []
    for m in mounts if isinstance(mounts, (list, tuple)) else [mounts]:
        if isinstance(m, str):
            parse_mount(m)   # a ValueError saying the form, at once
            out.append(m)
        elif isinstance(m, Mount):
            out.append((None, m))
        elif (isinstance(m, tuple) and len(m) == 2 and isinstance(m[1], Mount)
              and (m[0] is None or isinstance(m[0], str))):
            out.append(m)
        else:
            raise _refuse("mounts", "a mount ('[TOPIC=]X,Y,YAW[,flipped]' or a Mount), a sequence of them or a "
                          "dict of topic to mount", mounts)
    return tuple(out)


def _for_topic(topic, mount):
    """A dict's entry as an entry of the tuple: ``"TOPIC=X,Y,YAW"`` or ``(topic, Mount)``."""
    if isinstance(mount, Mount):
        return topic or None, mount
    if isinstance(mount, str) and topic:
        return f"{topic}={mount.rpartition('=')[2]}"
    return mount


def _sensors(sensors):
    if sensors is None:
        return None
    if isinstance(sensors, Mapping):
        pairs = tuple((str(k), v) for k, v in sensors.items())
        if all(isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v) for _, v in pairs):
            return pairs
    elif isinstance(sensors, (list, tuple)) and all(isinstance(s, str) for s in sensors) and sensors:
        return tuple(sensors)
    elif isinstance(sensors, tuple) and _by_angle(sensors):
        return sensors
    raise _refuse("sensors", "a sequence of sonar names, a dict of sonar name to angle (rad) or None", sensors)


def _by_angle(sensors: tuple) -> bool:
    return bool(sensors) and all(isinstance(s, tuple) and len(s) == 2 for s in sensors)


def _limits(limits):
    if limits is None:
        return None
    try:
        low, high = (float(v) for v in limits)
    except (TypeError, ValueError):
        low = high = math.nan
    if not (-2 * math.pi <= low < high <= 2 * math.pi) or isinstance(limits, str):
        raise _refuse("limits", "a pair (low, high) of radians with -2 pi <= low < high <= 2 pi or None", limits)
    return low, high


# ---------------------------------------------------------------------- helpers
def mount_options(mounts) -> dict:
    """``mounts`` (as :class:`Reading` keeps or takes them) as a dict of topic (None: every topic) to Mount."""
    out = {}
    for m in _mounts(mounts) or ():
        topic, mount = parse_mount(m) if isinstance(m, str) else m
        out[topic] = mount
    return out


def reading_given(fragments="auto", mounts=None, echo: str = "first") -> dict:
    """The options of a bag's reading given otherwise than by default, as a task's metadata keeps them.

    Only these enter it, so that a task made before they existed keeps its digest.

    >>> reading_given(mounts="/rear=-0.3,0,180,flipped", echo="last")
    {'mounts': {'/rear': 'x=-0.3 m, y=0 m, yaw=180 deg, upside down, from option'}, 'echo': 'last'}
    """
    given = {}
    if fragments != "auto":
        given["fragments"] = fragments
    if mounts is not None:
        given["mounts"] = {topic or "every scan topic": m.describe() for topic, m in mount_options(mounts).items()}
    if echo != "first":
        given["echo"] = echo
    return given


def reading_of(who: str, reading, options: dict, stacklevel: int = 3) -> Reading:
    """The :class:`Reading` a reader was given: ``reading``, or (deprecated) a topic and the options as keywords.

    ``who`` names the reader in the :class:`FutureWarning` that the keywords
    are deprecated; an unknown keyword is refused, naming the options.
    """
    if isinstance(reading, Reading) and not options:
        return reading
    if reading is not None and not isinstance(reading, Reading):
        options = {"topic": reading, **options}   # the old second argument, the scans' topic
        reading = None
    if options:
        given = ", ".join(f"{k}=..." for k in options)
        warnings.warn(f"{who}(path, {given}) is deprecated and will be removed in a future release: give the "
                      f"options as a Reading, {who}(path, Reading({given})) (novelty.io.Reading).",
                      FutureWarning, stacklevel=stacklevel)
    return (reading or Reading()).replace(**options)


def takes_reading_options(func: Callable) -> Callable:
    """Say, in ``func``'s signature, that its ``**options`` are :class:`Reading`'s, one keyword each.

    A task given its options flat (a suite's ``sectors = 8``) takes them
    as ``**options`` and makes a :class:`Reading` of them; its signature
    (:func:`inspect.signature`, which the registries read to check a
    suite's options and list a task's parameters) then names them, with
    their defaults, in place of ``**options``.
    """
    signature = inspect.signature(func)
    own = [p for p in signature.parameters.values() if p.kind is not inspect.Parameter.VAR_KEYWORD]
    taken = {p.name for p in own}
    fields = [inspect.Parameter(f.name, inspect.Parameter.KEYWORD_ONLY, default=f.default)
              for f in dataclasses.fields(Reading) if f.name not in taken]
    func.__signature__ = signature.replace(parameters=own + fields)
    return func
