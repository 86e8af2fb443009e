"""A recording's scan messages in, one at a time, whole sweeps out: what a bag's reader and a live node share.

A bag's reader (:mod:`novelty.io.recording.bag_sweeps`) and a live node
(:mod:`novelty.rosnode`) see the same messages, one from a file, the other
as they arrive; :class:`SweepStream` is what both do with them:

1. **Whole scans** (:class:`~novelty.io.scans.assembly.Assembler`): a
   scanner's fragments of one revolution become one scan.
2. **Waiting for the poses**: a whole scan is held until the poses have
   moved past its time (:meth:`~novelty.io.frames.posing.Posing.ready`),
   so that its pose is interpolated, not extrapolated, or until a scan
   :data:`WAIT` seconds younger has come; held scans leave in time order,
   none before a message a scanner still holds while it learns its pattern
   of fragments (at most :data:`~novelty.io.scans.assembly.LEARN_SECONDS`).
   The scans held hold at most :data:`~novelty.io.ros.caps.MAX_WAITING_BEAMS`
   beams: beyond, the oldest go on with the pose known then.
3. **Mounts** (:class:`Placing`): each sensor's frame placed in the base
   frame through the tree, or by the user's ``mounts`` where the tree has
   no transform for it (a user's mount also overrides the tree's, and says
   so); with neither, the sensor is taken at the robot's centre facing
   forward, and the report says so; its beams placed by the scans layer's
   one-message step (:class:`~novelty.io.scans.sweeps.SweepMaker`).
4. **Several sensors** (:class:`~novelty.io.scans.merge.Merger`): their
   sweeps merged within ``tolerance``.

The stream is fed scans (:meth:`SweepStream.push`); what it waits on (the
poses) is fed to its posing, and :meth:`SweepStream.release` lets go the
scans that may go now. A bag's reader releases at each scan; a live node
also at each pose, and after the scans stop (``stalled``).
"""

from __future__ import annotations

import heapq
import itertools
import math

from ..bags.read_report import ReadReport
from ..frames.mounts import Mount
from ..frames.posing import Posing
from ..frames.tf import TfError
from ..ros import caps
from ..ros.messages import LaserScan, Sweep
from ..scans.assembly import LEARN_SECONDS, Assembler
from ..scans.merge import Merger
from ..scans.sweeps import SweepMaker
from .reading import Reading

__all__ = ["SweepStream", "Placing", "WAIT"]

#: Seconds of the recording a scan waits for the poses after its time.
WAIT = 1.0


class SweepStream:
    """Whole sweeps of the scan ``topics``, their messages pushed one at a time (see the module docstring).

    Parameters
    ----------
    topics : list of str
        The scans' topics (several: sensors merged into one sweep).
    reading : Reading
        Its ``fragments``, ``mounts`` and ``tolerance``.
    posing : Posing
        The tree, the base frame and the poses, fed by the caller.
    report : ReadReport
        Filled as the stream goes (mounts; assembly and merging at :meth:`flush`).
    wait : float, default=WAIT
        Seconds of the scans' time a scan waits for the poses.
    """

    def __init__(self, topics: list[str], reading: Reading, posing: Posing, report: ReadReport,
                 wait: float = WAIT):
        self.topics, self.posing, self.report, self.wait = list(topics), posing, report, float(wait)
        self.placing = Placing(posing, reading.mount_map(), report)
        self.assemblers = {t: Assembler(reading.fragments, t) for t in self.topics}
        self.merger = Merger(self.topics, reading.tolerance) if len(self.topics) > 1 else None
        self.pending: list = []   # a heap of (stamp, count, topic, scan or cloud) waiting for the poses past their time
        self._counter = itertools.count()
        self.waiting = 0   # the beams (or points) of the scans held

    def push(self, topic: str, msg) -> None:
        """Take one message of a scan topic: a :class:`LaserScan`, or a point cloud ``(stamp, frame, points)``."""
        if isinstance(msg, tuple):   # a point cloud: whole as it comes
            assembler = self.assemblers[topic]
            assembler.messages += 1
            assembler.scans += 1
            self.hold(topic, msg[0], msg)
        elif isinstance(msg, LaserScan):
            for whole in self.assemblers[topic].push(msg):
                self.hold(topic, whole.stamp, whole)
        else:
            raise ValueError(f"{topic}: the scans are LaserScan, MultiEchoLaserScan or PointCloud2 messages; got a "
                             f"{type(msg).__name__}.")

    def hold(self, topic: str, stamp: float, scan) -> None:
        heapq.heappush(self.pending, (stamp, next(self._counter), topic, scan))
        self.waiting += _beams(scan)

    def release(self, now: float, stalled: bool = False) -> list[Sweep]:
        """The sweeps of the held scans that may go at ``now`` (the newest scan's time), in time order.

        A scan goes once it is :meth:`ready`, or is :attr:`wait` seconds older
        than ``now``, or (``stalled``) whatever it waits for, or when the scans
        held exceed their bound.
        """
        crowded = self.waiting > caps.MAX_WAITING_BEAMS
        # a topic still learning its fragments decides at last, LEARN_SECONDS after its first message held
        for topic, assembler in self.assemblers.items():
            if assembler.holding_since < (math.inf if crowded else now - LEARN_SECONDS):
                for whole in assembler.settle():
                    self.hold(topic, whole.stamp, whole)
        # in time order across the topics: none before a message a topic still holds (learning its fragments)
        held = min(a.holding_since for a in self.assemblers.values())
        out = []
        while self.pending and self.pending[0][0] <= held:
            stamp, _, topic, scan = self.pending[0]
            if not (stalled or stamp < now - self.wait or self.ready(topic, scan, stamp)
                    or self.waiting > caps.MAX_WAITING_BEAMS):
                break
            heapq.heappop(self.pending)
            self.waiting -= _beams(scan)
            whole = self.sweep(topic, scan, stamp)
            if whole is not None:
                out.append(whole)
        return out

    def ready(self, topic: str, scan, stamp: float) -> bool:
        """Whether a held scan has what it waits for: the poses past its time."""
        return self.posing.ready(stamp)

    def sweep(self, topic: str, scan, stamp: float) -> Sweep | None:
        """A held scan as a sweep, posed and placed; merged with the other sensors' (None: its partners to come)."""
        sweep = self.placing.sweep(topic, scan, self.posing.pose(stamp))
        return sweep if self.merger is None else self.merger.push(topic, sweep)

    def flush(self) -> list[Sweep]:
        """The sweeps of every scan still held (the messages have ended), and the report's account."""
        for topic, assembler in self.assemblers.items():
            for whole in assembler.flush():
                self.hold(topic, whole.stamp, whole)
            self.report.assembly[topic] = (assembler.messages, assembler.scans, assembler.incomplete,
                                           assembler.per_revolution)
        out = self.release(math.inf)
        if self.merger is not None:
            self.report.merged = (self.merger.merged, self.merger.dropped + len(self.merger.latest))
        return out


class Placing:
    """Each sensor's mount looked up in the tree (once where it does not move); its beams placed by a SweepMaker."""

    def __init__(self, posing: Posing, mounts: dict, report: ReadReport):
        self.posing, self.mounts, self.report = posing, mounts, report
        self.fixed: dict[str, Mount] = {}
        self.maker = SweepMaker(posing.base)

    @property
    def base(self) -> str:
        return self.posing.base

    def given(self, topic: str) -> Mount | None:
        """The user's mount for ``topic`` (or for every topic), if any."""
        return self.mounts.get(topic, self.mounts.get(None))

    def mount(self, topic: str, frame: str, time: float) -> Mount:
        if topic in self.fixed:
            return self.fixed[topic]
        given = self.given(topic)
        if given is not None:
            self.report.mounts[topic] = given.describe() + _overridden(self.posing.probe, self.base, frame)
            self.fixed[topic] = given
            return given
        if not frame or frame == self.base or not self.base:
            self.report.mounts[topic] = "at the robot's centre, facing forward" + (
                "" if frame == self.base and frame else " (assumed: no base frame or no sensor frame to place "
                f"{frame or 'it'} by; give --mount)")
            self.fixed[topic] = Mount(origin="the scan's own frame" if frame == self.base and frame else "assumed")
            return self.fixed[topic]
        tree, probe = self.posing.tree, self.posing.probe
        try:
            placement = tree.lookup(self.base, frame, time)
        except TfError:
            try:   # not yet in the tree at this time: the transform as /tf first gave it
                placement, tree = probe.lookup(self.base, frame, time), probe
            except TfError as exc:
                self.report.mounts[topic] = f"at the robot's centre, facing forward (assumed: {exc} Give --mount)"
                self.fixed[topic] = Mount()
                return self.fixed[topic]
        chain = probe.chain(frame)
        chain = chain[:chain.index(self.base) + 1] if self.base in chain else chain
        mount = Mount(placement, f"tf ({' -> '.join(reversed(chain))})")
        if probe.is_static(self.base, frame):
            self.fixed[topic] = mount
        self.report.mounts.setdefault(topic, mount.describe())
        return mount

    def sweep(self, topic: str, scan, pose) -> Sweep:
        """A whole scan (or a point cloud: ``(stamp, frame, points)``) as a sweep in the base frame."""
        self.maker.frame = self.base
        if isinstance(scan, tuple):
            stamp, frame, points = scan
            return self.maker.cloud(stamp, points, self.mount(topic, frame, stamp), pose, topic)
        return self.maker(scan, self.mount(topic, scan.frame, scan.stamp), pose, topic)


def _beams(scan) -> int:
    """A scan's beams, or a point cloud's ``(stamp, frame, points)`` points."""
    return len(scan[2]) if isinstance(scan, tuple) else len(scan.ranges)


def _overridden(tree, base: str, frame: str) -> str:
    if base and frame and tree.has(frame) and tree.has(base):
        return f" (the bag's own transform {base} -> {frame} is not used)"
    return ""
