"""A bag's frames: its tf tree, the robot's base frame in it, and where the robot's poses come from.

- **The tree** (:class:`~.tf.TfBuffer`): ``/tf_static`` is read whole first
  (static transforms are true at every time, whenever recorded), ``/tf``
  as the messages come; the first messages of ``/tf`` are looked at before
  anything else, to know the frames the tree will hold.
- **The base frame**: the user's, else REP 105's ``base_link``, falling
  back to ``base_footprint`` where the tree has no ``base_link``.
- **Poses**: the base frame's pose (x, y, yaw) in its tree's root (odom,
  or map) at a time, from ``/tf`` by default when it holds a moving chain
  to the base frame, or from an odometry or pose topic, interpolated at
  the time asked; none before the first. ``/tf_static`` as a pose topic is
  refused (static transforms do not move with the robot), and so is a
  ``tf`` pose topic that holds no moving chain to the base frame, with the
  frames and chains it does hold.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ..ros.messages import Pose, Transform
from ..bags.report import ReadReport
from ..bags.rosbag import POSE_TYPES, TF_TYPES, Bag
from .tf import TfBuffer, TfError

__all__ = ["Posing"]

#: The first messages of /tf read to learn its frames before the scans are read.
PROBE = 200
_WORLD, _ROBOT = "pose source", "robot"


class Posing:
    """An open bag's frames and poses (see the module docstring).

    Attributes
    ----------
    tree : TfBuffer
        The static transforms, and the moving ones as :meth:`feed` is given them.
    base : str
        The base frame ("" where the bag has no tree).
    topics : list of str
        The topics to read along with the scans (``/tf``, a pose topic) so that
        :meth:`feed` keeps the tree and the poses current.
    """

    def __init__(self, bag: Bag, pose_topic: str | None, base_frame: str | None, report: ReadReport,
                 moving_mounts: bool = True):
        tf = [t for t, kind in bag.types.items() if kind in TF_TYPES]
        static = [t for t in tf if t.rstrip("/").endswith("tf_static")]
        moving = [t for t in tf if t not in static]
        _check_pose_topic(bag, pose_topic, static)
        self.path, self.report = bag.path, report
        self.tree, self.probe = TfBuffer(), None
        if static:
            for _, where, transforms in bag.messages(static):
                self._add(self.tree, transforms, where)
        self.probe = self._probe(bag, moving)
        self.base = self._base_frame(base_frame)
        self.source = self._source(bag, pose_topic, moving)
        self.track = TfBuffer() if self.source == "topic" else self.tree
        follow = moving if moving and (self.source == "tf" or (moving_mounts and self._moving_below_base())) else []
        self.topics = follow + ([pose_topic] if self.source == "topic" else [])
        self.pose_from = pose_topic if self.source == "topic" else ", ".join(moving)

    def feed(self, msg, where=None) -> bool:
        """Take a message of :attr:`topics` (transforms or a pose; ``where`` it is, for a transform skipped);
        False for anything else."""
        if isinstance(msg, list):
            self._add(self.tree, msg, where)
            return True
        if isinstance(msg, Pose):
            self._add(self.track, [Transform(msg.stamp, _WORLD, _ROBOT, (msg.x, msg.y, 0.0),
                                             (0.0, 0.0, math.sin(msg.theta / 2), math.cos(msg.theta / 2)))], where)
            return True
        return False

    def ready(self, stamp: float) -> bool:
        """Whether the poses have reached past ``stamp`` (a lookup there interpolates)."""
        if self.source is None:
            return True
        try:
            if self.source == "topic":
                return stamp <= self.track.newest(_WORLD, _ROBOT)
            return stamp <= self.track.newest(self.track.root(self.base), self.base)
        except TfError:   # the chain not yet whole in the tree
            return False

    def pose(self, stamp: float) -> np.ndarray | None:
        """The base frame's (x, y, yaw) at ``stamp``; None before the first pose (or long after the last)."""
        if self.source is None:
            return None
        try:
            if self.source == "topic":
                pose = np.array(self.track.lookup(_WORLD, _ROBOT, stamp).planar)
            else:
                pose = np.array(self.track.lookup(self.track.root(self.base), self.base, stamp).planar)
        except TfError:
            return None
        if not np.isfinite(pose).all():   # finite samples far apart interpolate beyond a double
            raise ValueError(f"{self.path}: the robot's pose at {stamp:.3f} s, interpolated from {self.pose_from}, "
                             f"is not finite (x {pose[0]}, y {pose[1]}, yaw {pose[2]}).")
        return pose

    def _add(self, tree: TfBuffer, transforms, where) -> None:
        """Each transform into ``tree``; one it refuses is skipped and counted, as tf2 skips it."""
        for transform in transforms:
            try:
                tree.add(transform)
            except TfError as exc:
                if self.report is not None and tree is not self.probe:
                    self.report.skip(where, str(exc))

    # -------------------------------------------------------------- setting up
    def _probe(self, bag: Bag, moving: list[str]) -> TfBuffer:
        """The static tree with the moving frames of /tf's first messages: the frames the tree will hold."""
        probe = TfBuffer(tolerance=math.inf)
        for child in self.tree.frames:
            parent = self.tree.parent(child)
            if parent is not None:
                placed = self.tree.lookup(parent, child, 0.0)
                probe.add(Transform(0.0, parent, child, placed.translation, placed.rotation, True))
        self.probe = probe   # its refusals are counted when the tree meets them
        if moving:
            for _, where, transforms in itertools.islice(bag.messages(moving), PROBE):
                self._add(probe, transforms, where)
        return probe

    def _base_frame(self, base_frame: str | None) -> str:
        report = self.report
        if base_frame is not None:
            report.base_frame, report.base_reason = base_frame.strip("/"), "as given"
            return report.base_frame
        for name, reason in (("base_link", "REP 105's default"),
                             ("base_footprint", "REP 105's fallback: the tf tree has no base_link")):
            if self.probe.has(name):
                report.base_frame, report.base_reason = name, reason
                return name
        if self.probe.frames:
            report.notes.append(f"the tf tree has neither base_link nor base_footprint ({self.probe.describe()}); "
                                "give --base-frame to place the sensors and look poses up")
        return ""

    def _source(self, bag: Bag, pose_topic: str | None, moving: list[str]) -> str | None:
        """``"tf"``, ``"topic"`` or None."""
        if pose_topic is not None and bag.types[pose_topic] not in TF_TYPES:
            self.report.poses = f"from {pose_topic}, interpolated at each scan's time"
            return "topic"
        base, probe = self.base, self.probe
        chain = probe.chain(base) if base and probe.has(base) else [base]
        path = " -> ".join(reversed(chain))
        if moving and len(chain) > 1 and not probe.is_static(chain[-1], base):
            self.report.poses = f"from {', '.join(moving)}: {path}, interpolated at each scan's time"
            return "tf"
        if pose_topic is not None:
            why = f"its chain {path} does not move" if len(chain) > 1 else "it has no parent there"
            raise TfError(f"pose_topic {pose_topic} holds no pose for the base frame {base or '(none)'!r}: {why}; "
                          f"the frames: {', '.join(probe.frames) or 'none'}; the tree: {probe.describe()} "
                          "(give --base-frame, or an odometry topic).")
        self.report.poses = "none: no pose topic given" + (
            f", and {', '.join(moving)} holds no moving chain to {base or 'a base frame'}" if moving else "")
        return None

    def _moving_below_base(self) -> bool:
        """Whether a frame below the base frame moves (a mount that /tf must be followed for)."""
        probe, base = self.probe, self.base
        return bool(base) and any(base in probe.chain(f)[1:] and not probe.is_static(base, f) for f in probe.frames)


def _check_pose_topic(bag: Bag, pose_topic: str | None, static_topics: list[str]) -> None:
    if pose_topic is None:
        return
    bag.check([pose_topic])
    if pose_topic in static_topics:
        raise ValueError(f"pose_topic {pose_topic} holds static transforms (the sensors' mounts, true at every "
                         "time): they do not move with the robot; its poses are on /tf or an odometry topic.")
    if bag.types[pose_topic] not in POSE_TYPES:
        raise ValueError(f"pose_topic {pose_topic} must hold poses (one of {', '.join(POSE_TYPES)}); it holds "
                         f"{bag.types[pose_topic]}.")
