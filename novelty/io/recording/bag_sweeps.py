"""A bag's laser messages as sweeps in the robot's base frame: assembled, placed, posed and merged.

What a robot's recording holds beyond one centred laser, read as ROS's own
tools would (tf2 looks transforms up through the tree at each message's
time; laser assemblers and mergers put scans into one frame before anything
reads them):

1. **Whole scans** (:mod:`novelty.io.scans.assembly`): a scanner's fragments of one
   revolution become one scan.
2. **The tree, the base frame and the poses** (:mod:`novelty.io.frames.posing`); a scan
   waits until the poses have moved past its time (at most
   :data:`~novelty.io.recording.streaming.WAIT` seconds of the recording),
   so that its pose is interpolated, not extrapolated, and, with several
   topics, until none still learns its fragments (at most
   :data:`~novelty.io.scans.assembly.LEARN_SECONDS`); the scans waiting
   hold at most :data:`~novelty.io.ros.caps.MAX_WAITING_BEAMS` beams
   (beyond, the oldest go on with the pose known then).
3. **Mounts** (:mod:`novelty.io.frames.mounts`): each sensor's frame placed in the base
   frame through the tree, or by the user's ``mounts`` where the bag holds
   no transform (a user's mount also overrides the bag's, and says so; a
   mount for a topic not read is refused); with neither, the sensor is
   taken at the robot's centre facing forward, and the report says so; its
   beams placed by the scans layer's one-message step
   (:class:`novelty.io.scans.sweeps.SweepMaker`), as a live node places them.
4. **Several sensors** (:mod:`novelty.io.scans.merge`): their sweeps merged within ``tolerance``.

The steps after reading a message are :class:`~novelty.io.recording.streaming.SweepStream`'s, a message
at a time, as a live node takes them; this module reads the bag and feeds it.
"""

from __future__ import annotations

from typing import Iterator

from ..bags.read_report import ReadReport
from ..bags.rosbag import Bag
from ..frames.posing import Posing
from ..ros.messages import Sweep
from ..scans.assembly import Assembler
from .reading import Reading
from .streaming import WAIT, Placing, SweepStream

__all__ = ["bag_sweeps", "LASER_TYPES", "WAIT", "holds"]

#: The bag message types read as sweeps.
LASER_TYPES = ("sensor_msgs/msg/LaserScan", "sensor_msgs/msg/MultiEchoLaserScan", "sensor_msgs/msg/PointCloud2")


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
    stream = SweepStream(topics, reading, posing, report)
    messages = bag.messages(topics + posing.topics, nonempty=topics, echo=reading.echo)
    if stream.merger is None and not posing.topics:
        # one sensor, nothing to wait for: each whole scan's sweep as it comes, in the topic's order
        yield from _direct(messages, topics[0], stream.assemblers[topics[0]], stream.placing, report)
        return
    for topic, where, msg in messages:
        if posing.feed(msg, where):
            continue
        stream.push(topic, msg)
        yield from stream.release(msg[0] if isinstance(msg, tuple) else msg.stamp)
    yield from stream.flush()


def _direct(messages, topic: str, assembler: Assembler, placing: Placing, report: ReadReport) -> Iterator[Sweep]:
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



def holds(topics, kinds) -> str:
    """``/a holds T`` or ``/a, /b hold T, U``."""
    return f"{', '.join(topics)} {'holds' if len(topics) == 1 else 'hold'} {', '.join(sorted(kinds))}"
