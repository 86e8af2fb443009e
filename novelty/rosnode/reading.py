"""Live messages read as a bag's are read: one message at a time in, whole scans' inputs out.

``novelty run`` reads a bag through :func:`novelty.io.recording.bag_sweeps.bag_sweeps`,
which feeds each message to a :class:`~novelty.io.recording.streaming.SweepStream`:
fragments assembled, each sensor placed through its mount in the tf tree,
the robot's pose looked up at each scan's time, several sensors merged; each
sweep is then reduced to the paper's ring (:class:`~novelty.io.scans.sweep_rings.RingMaker`)
or to the ``points`` input (:class:`~novelty.io.scans.points.PointsMaker`),
as a :class:`~novelty.io.recording.reading.Reading` says. A live node has the
same messages, as they arrive; :class:`LiveReading` takes them one at a time
(their bytes, decoded by the bag reader's own decoders) and gives the same
inputs through the same stream.

What a bag reader knows before it reads a scan, a live one learns as the
messages come:

- **the tree** (:class:`LivePosing`): ``/tf_static`` (latched: its
  publishers send it to every new subscriber) and ``/tf`` as they arrive. The
  base frame is the one given, else REP 105's ``base_link``, else
  ``base_footprint``, once the tree holds one; poses come from ``/tf`` once it
  holds a moving chain up to the base frame (or from a pose topic), in the
  root of its tree unless a fixed frame is given;
- **waiting**: a scan is held until what it needs has arrived (its sensor's
  place in the tree at the first scan of a sensor; its pose, for the
  ``points`` input: the transforms past its time, so that the pose is
  interpolated, not extrapolated), or until a scan ``timeout`` seconds
  younger has arrived (the bag reader's rule, with its
  :data:`~novelty.io.recording.streaming.WAIT`), or until no scan has come
  for ``timeout`` seconds of the node's clock (a stream that stopped: then a
  scanner still learning its pattern of fragments learns it from what it
  holds). Held scans leave in time order, as the bag reader's do.

A scan whose pose never came is skipped for the ``points`` input and
counted; a ring does not need one. :attr:`LiveReading.skipped` counts every
scan left out, by reason.

Shares its name with novelty/io/recording/reading.py: the live node's reading, built on that
Reading.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, replace

import numpy as np

from ..io.bags.read_report import ReadReport
from ..io.frames.posing import Posing
from ..io.frames.tf import TfBuffer, TfError
from ..io.recording.reading import Reading
from ..io.recording.streaming import WAIT, SweepStream
from ..io.ros.caps import Where
from ..io.ros.decoders import decode, largest
from ..io.ros.messages import Pose, RangeReading, Transform
from ..io.scans.points import PointsMaker
from ..io.scans.sonar_rings import SonarRings
from ..io.scans.sweep_rings import RingMaker
from ..sonar.preprocessing import preprocess

__all__ = ["LiveReading", "LivePosing", "Row", "TF_TOPICS"]

#: The transforms' topics a node follows (tf2's).
TF_TOPICS = ("/tf", "/tf_static")
_WORLD, _ROBOT = "pose source", "robot"


@dataclass(frozen=True, eq=False)
class Row:
    """One whole scan's input: its time, the row for the detector, the robot's pose (or None), what it was read from.

    ``ranges`` are the scan's beams as read (cleaned: NaN where a beam gave no
    information) or a sonar ring's; ``frame`` the frame its ring is seen from
    (the base frame); ``arrival`` the node's clock when the message that
    completed the scan arrived.
    """

    time: float
    x: np.ndarray
    pose: np.ndarray | None
    ranges: np.ndarray
    frame: str = ""
    arrival: float = math.nan


class LivePosing(Posing):
    """:class:`~novelty.io.frames.posing.Posing` learnt from live transforms instead of a bag's look-ahead.

    The tree is fed as the messages arrive; the base frame and the source of
    the poses are decided once the tree can tell (:meth:`decide`), or when
    the first scan has waited long enough (``final=True``): then as the bag
    reader decides them from what it read ahead.
    """

    def __init__(self, pose_topic: str | None, base_frame: str | None, fixed_frame: str | None,
                 report: ReadReport):
        self.tree, self.probe = TfBuffer(), TfBuffer(tolerance=math.inf)
        self.report, self.pose_topic, self.given_base = report, pose_topic, base_frame or None
        self.fixed = fixed_frame.strip("/") if fixed_frame else None
        self.base = self.source = None
        self.track = TfBuffer() if pose_topic else self.tree
        self.topics = [pose_topic] if pose_topic else []
        self.decided = False

    def feed(self, msg) -> bool:
        if isinstance(msg, list):
            self.probe.add_all(msg)
        return super().feed(msg)

    def decide(self, final: bool = False) -> bool:
        """Decide the base frame and the poses' source if the tree can tell (or ``final``); whether decided."""
        if self.decided:
            return True
        base = self._base()
        moving = bool(base) and self.probe.has(base) and not self.probe.is_static(self.probe.root(base), base)
        if not final and not (base and (self.pose_topic or moving)):
            return False
        self.base = self.report.base_frame = base or ""
        if base:
            self.report.base_reason = "as given" if self.given_base else (
                "REP 105's default" if base == "base_link" else "REP 105's fallback: the tf tree has no base_link")
        if self.pose_topic:
            self.source, self.report.poses = "topic", f"from {self.pose_topic}, interpolated at each scan's time"
        elif moving:
            path = " -> ".join(reversed(self.probe.chain(base)))
            self.source, self.report.poses = "tf", f"from /tf: {path}, interpolated at each scan's time"
        else:
            self.report.poses = "none: no pose topic given, and /tf holds no moving chain to " + (
                base or "a base frame")
        self.decided = True
        return True

    def _base(self) -> str | None:
        if self.given_base:
            return self.given_base.strip("/")
        return next((name for name in ("base_link", "base_footprint") if self.probe.has(name)), None)

    def world(self) -> str:
        """The frame poses are looked up in: the fixed frame given, or the root of the base frame's tree."""
        if self.source == "topic":
            return _WORLD
        return self.fixed or self.track.root(self.base)

    def ready(self, stamp: float) -> bool:
        if self.source is None:
            return True
        try:
            robot = _ROBOT if self.source == "topic" else self.base
            return stamp <= self.track.newest(self.world(), robot)
        except TfError:
            return False

    def pose(self, stamp: float):
        if self.source is None:
            return None
        try:
            robot = _ROBOT if self.source == "topic" else self.base
            return np.array(self.track.lookup(self.world(), robot, stamp).planar)
        except TfError:
            return None

    def forget(self) -> None:
        """Forget every moving transform and pose (time jumped back); the static ones stay."""
        self.tree, self.probe = _statics(self.tree), _statics(self.probe, tolerance=math.inf)
        self.track = TfBuffer() if self.pose_topic else self.tree


def _statics(tree: TfBuffer, **options) -> TfBuffer:
    """A new tree of ``tree``'s static transforms only."""
    out = TfBuffer(**options)
    for child in tree.frames:
        parent = tree.parent(child)
        if parent is not None and tree.is_static(parent, child):
            placed = tree.lookup(parent, child, 0.0)
            out.add(Transform(0.0, parent, child, placed.translation, placed.rotation, True))
    return out


class LiveReading:
    """Live messages to the detector's inputs, as a bag's are read (see the module docstring).

    Parameters
    ----------
    reading : Reading
        How the scans are read (``novelty run``'s options on a recording): its ``topic`` the scans'
        topics, its ``inputs`` the ring or the ``points`` input.
    fixed_frame : str, optional
        The frame of the poses (default: the root of the base frame's tree, as ``novelty run``'s).
    one_a_beam : bool, default=False
        For the points input, at most one sector a beam (``reading.sectors`` were not given).
    timeout : float, default=WAIT
        Seconds of the scans' time a scan waits for its pose, and of the node's clock after the scans
        stop before the held ones are read without what they wait for.
    where : str
        Names the source in the errors of messages that cannot be read (the node's name).
    """

    def __init__(self, reading: Reading, *, fixed_frame: str | None = None, one_a_beam: bool = False,
                 timeout: float = WAIT, where: str = "live"):
        topics = reading.topics
        self.reading, self.scan_topics = reading, [topics] if isinstance(topics, str) else list(topics)
        self.points, self.threshold = reading.inputs == "points", reading.threshold
        self.sectors = None if self.points and one_a_beam else reading.sectors
        self.report = ReadReport()
        self.posing = LivePosing(reading.pose_topic, reading.base_frame, fixed_frame, self.report)
        self.rings = None if self.points else RingMaker(reading.sectors, reading.reduce, reading.limits,
                                                        reading.front, reading.clip)
        self.points_maker = None   # its sectors known at the first sweep when they are one a beam
        self.timeout, self.where = float(timeout), where
        self.skipped: Counter = Counter()
        self.problems: list[str] = []   # why scans were left out, for the node's log
        self.numbers: Counter = Counter()
        self.newest: dict[str, float] = {}
        self._start()

    def _start(self) -> None:
        self.stream = _LiveStream(self)
        self.sonars = None
        self.latest_scan = -math.inf
        self.last_arrival = math.inf   # the node's clock at the last scan message

    @property
    def topics(self) -> list[str]:
        """Every topic to follow: the scans', the transforms', the pose topic."""
        return self.scan_topics + list(TF_TOPICS) + self.posing.topics

    @property
    def assemblers(self) -> dict:
        return self.stream.assemblers

    # -------------------------------------------------------------- messages in
    def decode(self, topic: str, msgtype: str, data: bytes, arrival: float):
        """A message's bytes (ROS 1 serialization) decoded as a bag's are; a zero stamp takes ``arrival``."""
        self.numbers[topic] += 1
        where = Where(self.where, topic, self.numbers[topic])
        if len(data) > largest(msgtype):
            raise where.error("length", f"{len(data):,} bytes; at most {largest(msgtype):,} are read for its type "
                              "(novelty.io.ros.caps).")
        msg = decode(msgtype, data, True, where, topic, static=topic.rstrip("/").endswith("tf_static"),
                     echo=self.reading.echo)
        return _restamped(msg, arrival)

    def push(self, topic: str, msg, clock: float) -> list[Row]:
        """Take one decoded message; the rows of the scans it lets go. ``clock``: the node's clock now (s)."""
        if isinstance(msg, (list, Pose)):
            self.posing.feed(msg)
            return self.release(clock)
        if topic not in self.stream.assemblers:
            raise ValueError(f"{topic} is not a scan topic of this reading ({', '.join(self.scan_topics)}).")
        if isinstance(msg, RangeReading):
            self.latest_scan, self.last_arrival = max(self.latest_scan, msg.stamp), clock
            return self._sonar(topic, msg, clock)
        self.stream.arrival = clock
        self.stream.push(topic, msg)
        stamp = msg[0] if isinstance(msg, tuple) else msg.stamp
        self.latest_scan, self.last_arrival = max(self.latest_scan, stamp), clock
        return self.release(clock)

    # -------------------------------------------------------------- rows out
    def release(self, clock: float) -> list[Row]:
        """The rows of the held scans that may go now (see the module docstring), in time order."""
        stalled = clock - self.last_arrival >= self.timeout
        if stalled:
            self._decide_patterns()
        return self._rows(self.stream.release(self.latest_scan, stalled))

    def flush(self) -> list[Row]:
        """Every held scan's row, whatever it waits for (the stream has ended)."""
        self.stream.arrival = -math.inf
        return self._rows(self.stream.flush())

    def _decide_patterns(self) -> None:
        """The scanners still learning their pattern of fragments learn it from what they hold: the scans stopped."""
        self.stream.arrival = self.last_arrival
        for topic, assembler in self.stream.assemblers.items():
            if assembler.per_revolution is None and assembler.holding_since < math.inf:
                for whole in assembler.flush():
                    self.stream.hold(topic, whole.stamp, whole)

    def _rows(self, sweeps: list) -> list[Row]:
        out = []
        for sweep, arrival in sweeps:
            row = self._row(sweep, arrival)
            if row is not None:
                out.append(row)
        return out

    def _row(self, sweep, arrival: float) -> Row | None:
        """The sweep's row for the detector; None for a scan skipped (counted, its reason kept)."""
        try:
            if not self.points:
                return Row(sweep.time, preprocess(self.rings(sweep), self.threshold), sweep.pose, sweep.ranges,
                           sweep.frame, arrival)
            if sweep.pose is None:
                self.skipped["no pose at its time"] += 1
                return None
            if self.points_maker is None:
                self.sectors = self.sectors or min(self.reading.sectors, len(sweep.ranges))
                self.points_maker = PointsMaker(self.sectors, self.threshold)
            return Row(sweep.time, self.points_maker(sweep), sweep.pose, sweep.ranges, sweep.frame, arrival)
        except ValueError as exc:   # another geometry mid-stream: its beams cannot fill the sectors
            self._cannot(sweep.source, sweep.time, exc)
            return None

    def _cannot(self, topic: str, stamp: float, exc: Exception) -> None:
        self.skipped["its beams cannot make the input"] += 1
        self.problems.append(f"A scan on {topic} at {stamp:.3f} s cannot be read and is left out: {exc}")

    # -------------------------------------------------------------- sonars
    def _sonar(self, topic: str, reading: RangeReading, clock: float) -> list[Row]:
        """A sonar's reading into its ring, as a bag's are gathered (one topic a sonar, or sonars told by frame)."""
        if self.points:
            self.skipped["a sonar's reading: no points input"] += 1
            self.problems.append(f"{topic} carries sonar readings, which make the paper's ring, not the points input "
                                 "a map reads: give the map a laser's topic.")
            return []
        by_topic = len(self.scan_topics) > 1   # one topic a sonar, named by its topic; else told apart by frame
        if by_topic or not reading.sensor:
            reading = replace(reading, sensor=topic)
        gather = self.sonars
        if gather is None:
            gather = self.sonars = SonarRings(self.reading.sonar_order, self.reading.max_span)
        rings = []
        if gather.order is None and any(r.sensor == reading.sensor for r in gather.held):
            # every sensor met: in the order of their mounts where tf places them all, else by topic or by name
            order = self._mounting_angles(gather.held) or (self.scan_topics if by_topic else None)
            if order is not None:
                rings += gather.decide(order)
        rings += gather.push(reading)
        frame = self.posing.base or ""
        return [Row(time, preprocess(ranges, self.threshold), self.posing.pose(time), ranges, frame, clock)
                for time, ranges in rings]

    def _mounting_angles(self, held) -> dict | None:
        """Each sonar's mounting angle from the front, where the tf tree places every sonar's frame (as a bag's)."""
        base = self.posing.base or self.posing._base()
        frames = {r.sensor: r.frame for r in held}
        placed = {}
        for sensor, frame in frames.items():
            try:
                placed[sensor] = self.posing.probe.lookup(base, frame, 0.0).planar[2] % (2 * math.pi)
            except TfError:
                return None
        self.report.notes.append("sonars in the order of their mounting angles from tf: " + ", ".join(
            f"{s} {math.degrees(a):.0f} deg" for s, a in sorted(placed.items(), key=lambda kv: kv[1])))
        return placed

    # -------------------------------------------------------------- faults
    def jumped_back(self, topic: str, stamp: float) -> bool:
        """Whether ``stamp`` lies more than the timeout before the newest on ``topic`` (a loop, a reset)."""
        newest = self.newest.get(topic, -math.inf)
        self.newest[topic] = max(newest, stamp) if stamp >= newest - self.timeout else stamp
        return stamp < newest - self.timeout

    def restart(self) -> int:
        """Forget the held scans, the moving transforms and the scanners' patterns (time jumped back).

        Returns the number of held scans dropped (counted in :attr:`skipped`).
        """
        dropped = len(self.stream.pending)
        if dropped:
            self.skipped["held when time jumped back"] += dropped
        self.posing.forget()
        self.newest.clear()
        self._start()
        return dropped


class _LiveStream(SweepStream):
    """A :class:`~novelty.io.recording.streaming.SweepStream` whose scans wait for what a live reading learns late.

    A held scan waits until the base frame and the poses' source are decided
    (:meth:`LivePosing.decide`), its sensor can be placed (the tree joins its
    frame to the base frame, or a mount is given), and, for the points input
    only, its pose is ready. Each sweep comes with the node's clock when the
    message that completed its scan arrived; a scan that cannot be placed
    (a mount tilted out of the floor plane) is left out and counted.
    """

    def __init__(self, live: LiveReading):
        super().__init__(live.scan_topics, live.reading, live.posing, live.report, live.timeout)
        self.live = live
        self.arrival = math.nan              # the clock of the message being pushed
        self.arrivals: dict[int, float] = {}

    def hold(self, topic: str, stamp: float, scan) -> None:
        self.arrivals[id(scan)] = self.arrival
        super().hold(topic, stamp, scan)

    def ready(self, topic: str, scan, stamp: float) -> bool:
        if not self.live.posing.decide():
            return False
        if topic not in self.placing.fixed and not self._placeable(topic, scan):
            return False
        return not self.live.points or self.posing.ready(stamp)

    def _placeable(self, topic: str, scan) -> bool:
        frame, base = scan[1] if isinstance(scan, tuple) else scan.frame, self.posing.base
        if self.placing.given(topic) is not None or not frame or frame == base or not base:
            return True
        try:
            self.posing.probe.lookup(base, frame, 0.0)
            return True
        except TfError:
            return False

    def sweep(self, topic: str, scan, stamp: float):
        """The sweep and its arrival, or None (a part of several sensors' scan, or a scan left out)."""
        arrival = self.arrivals.pop(id(scan), math.nan)
        self.live.posing.decide(final=True)   # at the latest when a scan must go
        try:
            sweep = super().sweep(topic, scan, stamp)
        except ValueError as exc:
            self.live._cannot(topic, stamp, exc)
            return None
        return None if sweep is None else (sweep, arrival)


def _restamped(msg, arrival: float):
    """A zero header stamp (a driver that leaves it unset) takes the arrival time, as a bag's takes its record time."""
    if isinstance(msg, list):
        return msg if all(t.stamp > 0 for t in msg) else [
            t if t.stamp > 0 else Transform(arrival, t.parent, t.child, t.translation, t.rotation, t.static)
            for t in msg]
    if isinstance(msg, tuple):
        stamp, frame, points = msg
        return (stamp if stamp > 0 else arrival), frame, points
    return msg if msg.stamp > 0 else replace(msg, stamp=arrival)
