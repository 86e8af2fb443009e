"""A bag's laser messages as sweeps in the robot's base frame: assembled, placed, posed and merged.

What a robot's recording holds beyond one centred laser, read as ROS's own
tools would (tf2 looks transforms up through the tree at each message's
time; laser assemblers and mergers put scans into one frame before anything
reads them):

1. **Whole scans** (:mod:`novelty.io.scans.assembly`): a scanner's fragments of one
   revolution become one scan.
2. **The tree, the base frame and the poses** (:mod:`novelty.io.frames.posing`); a scan
   waits until the poses have moved past its time (at most :data:`WAIT`
   seconds of the recording), so that its pose is interpolated, not
   extrapolated, and, with several topics, until none still learns its
   fragments (at most :data:`~novelty.io.scans.assembly.LEARN_SECONDS`);
   the scans waiting hold at most :data:`~novelty.io.ros.caps.MAX_WAITING_BEAMS`
   beams (beyond, the oldest go on with the pose known then).
3. **Mounts** (:mod:`novelty.io.frames.mounts`): each sensor's frame placed in the base
   frame through the tree, or by the user's ``mounts`` where the bag holds
   no transform (a user's mount also overrides the bag's, and says so; a
   mount for a topic not read is refused); with neither, the sensor is
   taken at the robot's centre facing forward, and the report says so; its
   beams placed by the scans layer's one-message step
   (:class:`novelty.io.scans.sweeps.SweepMaker`), as a live node places them.
4. **Several sensors** (:mod:`novelty.io.scans.merge`): their sweeps merged within ``tolerance``.
"""

from __future__ import annotations

import heapq
import itertools
import math
from typing import Iterator

from ..bags.report import ReadReport
from ..bags.rosbag import Bag
from ..frames.mounts import Mount
from ..frames.posing import Posing
from ..frames.tf import TfError
from ..ros import caps
from ..ros.messages import Sweep
from ..scans.assembly import LEARN_SECONDS, Assembler
from ..scans.merge import Merger
from ..scans.sweeps import SweepMaker
from .reading import Reading

__all__ = ["bag_sweeps", "LASER_TYPES", "WAIT", "holds"]

#: The bag message types read as sweeps.
LASER_TYPES = ("sensor_msgs/msg/LaserScan", "sensor_msgs/msg/MultiEchoLaserScan", "sensor_msgs/msg/PointCloud2")
#: Seconds of the recording a scan waits for the poses after its time.
WAIT = 1.0


def bag_sweeps(bag: Bag, topics: list[str], reading: Reading | None = None,
               report: ReadReport | None = None) -> Iterator[Sweep]:
    """The sweeps of the laser ``topics`` of an open bag, read as ``reading`` says (see the module docstring)."""
    reading = Reading() if reading is None else reading
    report = report if report is not None else ReadReport()
    kinds = {bag.types[t] for t in topics}
    if not kinds <= set(LASER_TYPES):
        raise ValueError("Sweeps are read from LaserScan, MultiEchoLaserScan or PointCloud2 topics; "
                         f"{holds(topics, kinds)}.")
    mounts = reading.mount_map()
    stray = sorted(t for t in mounts if t is not None and t not in topics)
    if stray:
        raise ValueError(f"A mount is given for {', '.join(stray)}, which is not a scan topic read "
                         f"({', '.join(topics)}); a mount names the topic of its sensor's scans.")
    posing = Posing(bag, reading.pose_topic, reading.base_frame, report)
    placing = _Placing(posing, mounts, report)
    assemblers = {t: Assembler(reading.fragments, t) for t in topics}
    merger = Merger(topics, reading.tolerance) if len(topics) > 1 else None
    pending: list = []   # a heap of (stamp, count, topic, scan or cloud) waiting for the poses after their time
    counter = itertools.count()
    waiting = [0]   # the beams (or points) of the scans pending

    def release(now: float):
        crowded = waiting[0] > caps.MAX_WAITING_BEAMS
        # a topic still learning its fragments decides at last, LEARN_SECONDS after its first message held
        for topic, assembler in assemblers.items():
            if assembler.holding_since < (math.inf if crowded else now - LEARN_SECONDS):
                for whole in assembler.settle():
                    hold(topic, whole.stamp, whole)
        # in time order across the topics: none before a message a topic still holds (learning its fragments)
        held = min(a.holding_since for a in assemblers.values())
        while pending and pending[0][0] <= held and (pending[0][0] < now - WAIT or posing.ready(pending[0][0])
                                                     or waiting[0] > caps.MAX_WAITING_BEAMS):
            stamp, _, topic, scan = heapq.heappop(pending)
            waiting[0] -= _beams(scan)
            sweep = placing.sweep(topic, scan, posing.pose(stamp))
            whole = sweep if merger is None else merger.push(topic, sweep)
            if whole is not None:
                yield whole

    def hold(topic, stamp, scan):
        heapq.heappush(pending, (stamp, next(counter), topic, scan))
        waiting[0] += _beams(scan)

    messages = bag.messages(topics + posing.topics, nonempty=topics, echo=reading.echo)
    if merger is None and not posing.topics:
        # one sensor, nothing to wait for: each whole scan's sweep as it comes, in the topic's order
        yield from _direct(messages, topics[0], assemblers[topics[0]], placing, report)
        return
    for topic, where, msg in messages:
        if posing.feed(msg, where):
            continue
        if isinstance(msg, tuple):   # a point cloud (stamp, frame, points): whole as it comes
            assemblers[topic].messages += 1
            assemblers[topic].scans += 1
            hold(topic, msg[0], msg)
            yield from release(msg[0])
        else:
            for whole in assemblers[topic].push(msg):
                hold(topic, whole.stamp, whole)
            yield from release(msg.stamp)
    for topic, assembler in assemblers.items():
        for whole in assembler.flush():
            hold(topic, whole.stamp, whole)
        report.assembly[topic] = (assembler.messages, assembler.scans, assembler.incomplete,
                                  assembler.per_revolution)
    yield from release(math.inf)
    if merger is not None:
        report.merged = (merger.merged, merger.dropped + len(merger.latest))


def _direct(messages, topic: str, assembler: Assembler, placing: "_Placing", report: ReadReport) -> Iterator[Sweep]:
    for _, _, msg in messages:
        if isinstance(msg, tuple):   # a point cloud (stamp, frame, points): whole as it comes
            assembler.messages += 1
            assembler.scans += 1
            yield placing.sweep(topic, msg, None)
        else:
            for whole in assembler.push(msg):
                yield placing.sweep(topic, whole, None)
    for whole in assembler.flush():
        yield placing.sweep(topic, whole, None)
    report.assembly[topic] = (assembler.messages, assembler.scans, assembler.incomplete, assembler.per_revolution)


def _beams(scan) -> int:
    """A scan's beams, or a point cloud's ``(stamp, frame, points)`` points."""
    return len(scan[2]) if isinstance(scan, tuple) else len(scan.ranges)


def holds(topics, kinds) -> str:
    """``/a holds T`` or ``/a, /b hold T, U``."""
    return f"{', '.join(topics)} {'holds' if len(topics) == 1 else 'hold'} {', '.join(sorted(kinds))}"


class _Placing:
    """Each sensor's mount looked up in the bag's tree (once where it does not move); its beams placed by a SweepMaker."""

    def __init__(self, posing: Posing, mounts: dict, report: ReadReport):
        self.posing, self.base, self.mounts, self.report = posing, posing.base, mounts, report
        self.fixed: dict[str, Mount] = {}
        self.maker = SweepMaker(posing.base)

    def mount(self, topic: str, frame: str, time: float) -> Mount:
        if topic in self.fixed:
            return self.fixed[topic]
        given = self.mounts.get(topic, self.mounts.get(None))
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
        if isinstance(scan, tuple):
            stamp, frame, points = scan
            return self.maker.cloud(stamp, points, self.mount(topic, frame, stamp), pose, topic)
        return self.maker(scan, self.mount(topic, scan.frame, scan.stamp), pose, topic)


def _overridden(tree, base: str, frame: str) -> str:
    if base and frame and tree.has(frame) and tree.has(base):
        return f" (the bag's own transform {base} -> {frame} is not used)"
    return ""
