"""Live messages read as a bag's are read: one message at a time in, whole scans' inputs out.

``novelty run`` reads a bag through :func:`novelty.io.bag_sweeps.bag_sweeps`:
fragments assembled, each sensor placed through its mount in the tf tree,
the robot's pose looked up at each scan's time, several sensors merged, then
each sweep reduced to the paper's ring or to the ``points`` input. A live
node has the same messages, as they arrive; :class:`LiveReading` takes them
one at a time (their bytes, decoded by the bag reader's own decoders) and
gives the same inputs, through the same pieces (:class:`~novelty.io.assembly.Assembler`,
:class:`~novelty.io.tf.TfBuffer`, the bag reader's placing of sensors,
:class:`~novelty.io.merge.Merger`, :class:`~novelty.io.sweeps.RingMaker`,
:func:`~novelty.io.objects.points.sweep_points`).

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
  interpolated, not extrapolated), or until a scan :data:`~novelty.io.bag_sweeps.WAIT`
  seconds younger has arrived (the bag reader's rule), or until it has waited
  ``timeout`` seconds of the node's clock (a stream that stopped). Held scans
  leave in time order, as the bag reader's do.

A scan whose pose never came is skipped for the ``points`` input and
counted; a ring does not need one. :attr:`skipped` counts every scan left
out, by reason.
"""

from __future__ import annotations

import heapq
import itertools
import math
from collections import Counter
from dataclasses import dataclass, replace

import numpy as np

from ..io.assembly import Assembler
from ..io.bag_sweeps import WAIT, _Placing
from ..io.caps import Where
from ..io.decoders import decode, largest
from ..io.merge import Merger
from ..io.messages import LaserScan, Pose, Transform
from ..io.objects.points import sweep_points
from ..io.posing import Posing
from ..io.report import ReadReport
from ..io.sweeps import RingMaker, mount_options
from ..io.tf import TfBuffer, TfError
from ..sonar.preprocessing import preprocess

__all__ = ["LiveReading", "LivePosing", "Row", "TF_TOPICS", "POINTS_SECTORS"]

#: The transforms' topics a node follows (tf2's).
TF_TOPICS = ("/tf", "/tf_static")
#: The points input's sectors unless given (as ``novelty run``'s): one a beam for a sensor of fewer.
POINTS_SECTORS = 180
_WORLD, _ROBOT = "pose source", "robot"


@dataclass(frozen=True, eq=False)
class Row:
    """One whole scan's input: its time, the row for the detector, the robot's pose (or None), its sweep."""

    time: float
    x: np.ndarray
    pose: np.ndarray | None
    sweep: object
    #: the node's clock when the message that completed the scan arrived
    arrival: float = math.nan


class LivePosing(Posing):
    """:class:`~novelty.io.posing.Posing` learnt from live transforms instead of a bag's look-ahead.

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
    scan_topics : list of str
        The scans' topics (LaserScan, MultiEchoLaserScan, PointCloud2); several are merged.
    points : bool
        Give the ``points`` input (a detector that reads the robot's pose with each scan), else the ring.
    sectors, reduce, limits, front, threshold
        As ``novelty run`` on a recording (``limits`` and ``front`` in radians, ``threshold`` the paper's T).
    pose_topic, base_frame, fixed_frame, mounts, fragments, echo, tolerance
        As ``novelty run`` on a bag; ``fixed_frame`` the frame of the poses (default: the tree's root).
    timeout : float
        Seconds of the node's clock a scan waits at most for its transforms.
    where : str
        Names the source in the errors of messages that cannot be read (the node's name).
    """

    def __init__(self, scan_topics, *, points: bool = False, sectors: int | None = None, reduce="min",
                 limits=None, front: float = 0.0, threshold: float = 4.0, pose_topic: str | None = None,
                 base_frame: str | None = None, fixed_frame: str | None = None, mounts=None, fragments="auto",
                 echo: str = "first", tolerance: float = 0.1, timeout: float = WAIT, where: str = "live"):
        self.scan_topics, self.points, self.threshold = list(scan_topics), points, threshold
        self.report = ReadReport()
        self.posing = LivePosing(pose_topic, base_frame, fixed_frame, self.report)
        self.placing = _Placing(self.posing, mount_options(mounts), self.report)
        self.options = dict(fragments=fragments, tolerance=tolerance, echo=echo)
        self.sectors = sectors if sectors is not None or points else 16
        self.rings = None if points else RingMaker(self.sectors, reduce, limits, front)
        self.timeout, self.where = float(timeout), where
        self.skipped: Counter = Counter()
        self.problems: list[str] = []   # why scans were left out, for the node's log
        self.numbers: Counter = Counter()
        self.newest: dict[str, float] = {}
        self._start()

    def _start(self) -> None:
        fragments, tolerance = self.options["fragments"], self.options["tolerance"]
        self.assemblers = {t: Assembler(fragments, t) for t in self.scan_topics}
        self.merger = Merger(self.scan_topics, tolerance) if len(self.scan_topics) > 1 else None
        self.pending: list = []   # a heap of (stamp, count, topic, scan, arrival)
        self.counter = itertools.count()
        self.latest_scan = -math.inf
        self.last_arrival = math.inf   # the node's clock at the last scan message

    @property
    def topics(self) -> list[str]:
        """Every topic to follow: the scans', the transforms', the pose topic."""
        return self.scan_topics + list(TF_TOPICS) + self.posing.topics

    # -------------------------------------------------------------- messages in
    def decode(self, topic: str, msgtype: str, data: bytes, arrival: float):
        """A message's bytes (ROS 1 serialization) decoded as a bag's are; a zero stamp takes ``arrival``."""
        self.numbers[topic] += 1
        where = Where(self.where, topic, self.numbers[topic])
        if len(data) > largest(msgtype):
            raise where.error("length", f"{len(data):,} bytes; at most {largest(msgtype):,} are read for its type "
                              "(novelty.io.caps).")
        msg = decode(msgtype, data, True, where, topic, static=topic.rstrip("/").endswith("tf_static"),
                     echo=self.options["echo"])
        return _restamped(msg, arrival)

    def push(self, topic: str, msg, clock: float) -> list[Row]:
        """Take one decoded message; the rows of the scans it lets go. ``clock``: the node's time now (s)."""
        if isinstance(msg, (list, Pose)):
            self.posing.feed(msg)
            return self.release(clock)
        if topic not in self.assemblers:
            raise ValueError(f"{topic} is not a scan topic of this reading ({', '.join(self.scan_topics)}).")
        if isinstance(msg, tuple):   # a point cloud (stamp, frame, points): whole as it comes
            assembler = self.assemblers[topic]
            assembler.messages += 1
            assembler.scans += 1
            self._hold(topic, msg[0], msg, clock)
            stamp = msg[0]
        elif isinstance(msg, LaserScan):
            for whole in self.assemblers[topic].push(msg):
                self._hold(topic, whole.stamp, whole, clock)
            stamp = msg.stamp
        else:
            raise ValueError(f"{topic}: a scan topic's messages are LaserScan, MultiEchoLaserScan or PointCloud2; "
                             f"got a {type(msg).__name__}.")
        self.latest_scan, self.last_arrival = max(self.latest_scan, stamp), clock
        return self.release(clock)

    def _hold(self, topic, stamp, scan, clock) -> None:
        heapq.heappush(self.pending, (stamp, next(self.counter), topic, scan, clock))

    # -------------------------------------------------------------- rows out
    def release(self, clock: float) -> list[Row]:
        """The rows of the held scans that may go now (see the module docstring), in time order."""
        if clock - self.last_arrival >= self.timeout:
            self._decide_patterns()
        learning = [a.holding_since for a in self.assemblers.values() if a.per_revolution is None]
        held = min(learning, default=math.inf)
        out = []
        while self.pending and self.pending[0][0] <= held:
            stamp, _, topic, scan, arrival = self.pending[0]
            expired = stamp < self.latest_scan - self.timeout or clock - self.last_arrival >= self.timeout
            if not (self._ready(topic, scan, stamp) or expired):
                break
            heapq.heappop(self.pending)
            if not self.posing.decided:
                self._decided(final=True)
            row = self._row(topic, scan, stamp, arrival)
            if row is not None:
                out.append(row)
        return out

    def _decide_patterns(self) -> None:
        """The scanners still learning their pattern of fragments learn it from what they hold: the scans stopped."""
        for topic, assembler in self.assemblers.items():
            if assembler.per_revolution is None and assembler.holding_since < math.inf:
                for whole in assembler.flush():
                    self._hold(topic, whole.stamp, whole, self.last_arrival)

    def flush(self) -> list[Row]:
        """Every held scan's row, whatever it waits for (the stream has ended)."""
        for topic, assembler in self.assemblers.items():
            for whole in assembler.flush():
                self._hold(topic, whole.stamp, whole, -math.inf)
        return self.release(math.inf)

    def _decided(self, final: bool = False) -> bool:
        """Whether the base frame and the poses' source are decided (deciding them if the tree can tell)."""
        if not self.posing.decided and self.posing.decide(final):
            self.placing.base = self.posing.base
        return self.posing.decided

    def _ready(self, topic: str, scan, stamp: float) -> bool:
        """Whether what the scan needs has arrived: the tree's answers, its sensor's place, its pose."""
        if not self._decided():
            return False
        if topic not in self.placing.fixed and not self._placeable(topic, scan):
            return False
        return not self.points or self.posing.ready(stamp)

    def _placeable(self, topic: str, scan) -> bool:
        frame = scan[1] if isinstance(scan, tuple) else scan.frame
        base = self.posing.base
        if self.placing.mounts.get(topic, self.placing.mounts.get(None)) is not None or not frame or \
                frame == base or not base:
            return True
        try:
            self.posing.probe.lookup(base, frame, 0.0)
            return True
        except TfError:
            return False

    def _row(self, topic: str, scan, stamp: float, arrival: float) -> Row | None:
        """The scan's row; None for a part of several sensors' scan, or a scan skipped (counted, its reason kept)."""
        try:
            return self._input(topic, scan, stamp, arrival)
        except ValueError as exc:   # another geometry mid-stream, a tilted mount: this scan cannot be read
            self.skipped["its beams cannot make the input"] += 1
            self.problems.append(f"A scan on {topic} at {stamp:.3f} s cannot be read and is left out: {exc}")
            return None

    def _input(self, topic: str, scan, stamp: float, arrival: float) -> Row | None:
        pose = self.posing.pose(stamp)
        sweep = self.placing.sweep(topic, scan, pose)
        if self.merger is not None:
            sweep = self.merger.push(topic, sweep)
            if sweep is None:
                return None
        if not self.points:
            return Row(sweep.time, preprocess(self.rings(sweep), self.threshold), sweep.pose, sweep, arrival)
        if sweep.pose is None:
            self.skipped["no pose at its time"] += 1
            return None
        if self.sectors is None:
            self.sectors = min(POINTS_SECTORS, len(sweep.ranges))
        return Row(sweep.time, sweep_points([sweep], self.sectors, self.threshold)[0], sweep.pose, sweep, arrival)

    # -------------------------------------------------------------- faults
    def jumped_back(self, topic: str, stamp: float) -> bool:
        """Whether ``stamp`` lies more than :data:`WAIT` seconds before the newest on ``topic`` (a loop, a reset)."""
        newest = self.newest.get(topic, -math.inf)
        self.newest[topic] = max(newest, stamp) if stamp >= newest - WAIT else stamp
        return stamp < newest - WAIT

    def restart(self) -> int:
        """Forget the held scans, the moving transforms and the scanners' patterns (time jumped back).

        Returns the number of held scans dropped (counted in :attr:`skipped`).
        """
        dropped = len(self.pending)
        if dropped:
            self.skipped["held when time jumped back"] += dropped
        self.posing.forget()
        self.newest.clear()
        self._start()
        return dropped


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
