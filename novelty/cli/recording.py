"""Recordings (CARMEN logs, ROS bags) on the command line: their options as a Reading, and streaming their rings.

:func:`add_recording_options` adds the options that say how a recording is
read; :func:`recording_reading` makes of them the
:class:`~novelty.io.recording.reading.Reading` every reader takes.
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import numpy as np

from .._atomic import write_atomically
from ._common import UserError, format_cell

__all__ = ["add_recording_options", "recording_reading", "recording_rings", "recording_points", "pose_columns",
           "RowSink", "POINTS_SECTORS"]

#: the points input's sectors unless --sectors says: the habituating maps were measured on lasers with
#: 180 (benchmarks/suites/maps-exploration.toml); a sensor of fewer beams gets one sector a beam
POINTS_SECTORS = 180


def add_recording_options(parser) -> None:
    """The options that say which messages of a recording are the scans and how they become rings."""
    group = parser.add_argument_group(
        "recordings (--data a CARMEN log .log/.log.gz or a ROS bag .bag/.db3/.mcap; rings are "
        "preprocessed as the paper's, T = --range-threshold)")
    group.add_argument("--topic", metavar="TOPIC",
                       help="the scans: a LaserScan, MultiEchoLaserScan, PointCloud2 or Range topic; several "
                       "comma-separated (lasers merged into one ring, or one Range topic a sonar); or a CARMEN "
                       "message (default FLASER, or a bag's only scan topic)")
    group.add_argument("--pose-topic", metavar="TOPIC",
                       help="poses: an Odometry, PoseStamped or tf topic, or ODOM in a CARMEN log (default: a "
                       "CARMEN laser's own corrected pose; a bag's /tf where it holds the base frame's chain)")
    group.add_argument("--base-frame", metavar="FRAME",
                       help="the robot's frame in the bag's tf tree (default: base_link, else base_footprint, "
                       "as REP 105 says)")
    group.add_argument("--mount", action="append", metavar="[TOPIC=]X,Y,YAW[,flipped]",
                       help="where a laser sits on the robot (m, m, degrees; flipped: upside down) when the bag "
                       "holds no transform for it (repeatable, one a topic)")
    group.add_argument("--fragments", default="auto", metavar="N",
                       help="messages a revolution of a scanner that splits them: auto (detected), or N (1: "
                       "each message a whole scan)")
    group.add_argument("--echo", default="first", choices=("first", "last", "strongest"),
                       help="the echo of a MultiEchoLaserScan's beams read (default first)")
    group.add_argument("--tolerance", type=float, default=0.1, metavar="S",
                       help="several lasers' scans within S seconds are merged into one ring (default 0.1)")
    group.add_argument("--sectors", type=int, default=None, metavar="N",
                       help="laser beams reduced to N equal sectors (default 16, the paper's sonars; for a "
                       f"detector that reads the robot's pose with each scan, the habituating maps, "
                       f"{POINTS_SECTORS} or one a beam)")
    group.add_argument("--reduce", default="min", metavar="HOW",
                       help="a sector's beams to one range: min (a sonar's nearest echo), mean, median or "
                       "a percentile 0-100 (default min)")
    group.add_argument("--front", type=float, default=0.0, metavar="DEG",
                       help="the angle of the robot's front in the scans' frame, degrees (default 0: the base "
                       "frame's x axis)")
    group.add_argument("--stamps", action="store_true",
                       help="give the detector the messages' times as elapsed time (default: one step a "
                       "scan, as the paper presents one perception a step)")
    group.add_argument("--limits", metavar="LOW,HIGH",
                       help="the span cut into sectors, degrees from the front (default: the whole scan; all "
                       "round from the front for a scan all round)")


def _reduce(text: str):
    if text in ("min", "mean", "median"):
        return text
    try:
        return float(text)
    except ValueError:
        raise UserError(f"--reduce must be min, mean, median or a percentile; got {text!r}.") from None


def _limits(text: str | None):
    if text is None:
        return None
    try:
        low, high = (math.radians(float(v)) for v in text.split(","))
    except ValueError:
        raise UserError(f"--limits must be LOW,HIGH in degrees; got {text!r}.") from None
    return low, high


def _fragments(text: str):
    if text == "auto":
        return text
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise UserError(f"--fragments must be auto or a count >= 1; got {text!r}.")
    return n


def recording_reading(args, inputs: str = "ring"):
    """The :class:`~novelty.io.recording.reading.Reading` the command line's options say, for ``inputs``.

    The points input's sectors, unless ``--sectors`` says, are
    :data:`POINTS_SECTORS` (one a beam for a sensor of fewer: see
    :func:`recording_points`). A value the options do not allow is a
    :class:`UserError` with the reading's own message.
    """
    # deferred: the readers are loaded only for a recording
    from ..io.recording.reading import Reading
    from ..sonar.preprocessing import PAPER_THRESHOLD

    topic = None if args.topic is None else (args.topic.split(",") if "," in args.topic else args.topic)
    sectors = args.sectors if args.sectors is not None else (POINTS_SECTORS if inputs == "points" else 16)
    try:
        return Reading(topic=topic, pose_topic=args.pose_topic, base_frame=getattr(args, "base_frame", None),
                       mounts=getattr(args, "mount", None), fragments=_fragments(getattr(args, "fragments", "auto")),
                       echo=getattr(args, "echo", "first"), tolerance=getattr(args, "tolerance", 0.1),
                       sectors=sectors, reduce=_reduce(args.reduce), limits=_limits(args.limits),
                       front=math.radians(args.front), inputs=inputs, stamps=bool(getattr(args, "stamps", False)),
                       threshold=PAPER_THRESHOLD if args.range_threshold is None else args.range_threshold)
    except ValueError as exc:
        if inputs == "points" and "apply to the ring only" in str(exc):
            raise UserError("The points input reads each sector's nearest echo over the whole scan, placed in the "
                            "world by the robot's pose: no --reduce, --limits or --front.") from None
        raise UserError(str(exc)) from None


def recording_rings(args, report=None):
    """``(time, x, pose)`` for each ring of the recording ``--data``, ``x`` preprocessed; read as it goes.

    ``report`` (a :class:`novelty.io.bags.report.ReadReport`) is filled as the reading goes.
    """
    # deferred: the readers are loaded only for a recording
    from ..io.recording.readers import read_rings
    from ..sonar.preprocessing import preprocess

    reading = recording_reading(args)
    try:
        for ring in read_rings(args.data, reading, report=report):
            yield ring.time, preprocess(ring.ranges, reading.threshold), ring.pose
    except ImportError as exc:   # the optional rosbags: a message to install it, not a traceback
        raise UserError(str(exc)) from None


def recording_points(args, report=None):
    """``(time, row, pose)`` for each scan of ``--data`` that has a pose, ``row`` the ``points`` input.

    The input of the detectors that read the robot's pose with each scan
    (the habituating maps, :mod:`novelty.io.scans.points`): the pose, each
    sector's nearness and its end point in the world frame
    (:func:`novelty.io.scans.points.sweep_points`), :data:`POINTS_SECTORS`
    sectors unless ``--sectors`` says (one a beam for a sensor of fewer).
    Scans before the pose source's first message are left out, and
    ``report`` says how many; a recording with no pose at all is an error
    that says where poses come from.
    """
    # deferred: the readers are loaded only for a recording
    from ..io.recording.readers import read_sweeps
    from ..io.scans.points import sweep_points

    reading = recording_reading(args, "points")
    sectors = args.sectors
    without, scored = 0, 0
    try:
        for sweep in read_sweeps(args.data, reading, report=report):
            if sweep.pose is None:
                without += 1
                continue
            if sectors is None:
                sectors = min(reading.sectors, len(sweep.ranges))
            scored += 1
            yield sweep.time, sweep_points([sweep], sectors, reading.threshold)[0], sweep.pose
    except ImportError as exc:   # the optional rosbags: a message to install it, not a traceback
        raise UserError(str(exc)) from None
    if without and not scored:
        raise UserError(f"{args.detector} reads the robot's pose with each scan; none of the {without} scans of "
                        f"{args.data} had one: give --pose-topic (an Odometry, PoseStamped or tf topic; ODOM in "
                        "a CARMEN log).")
    if without and report is not None:
        report.notes.append(f"{without} scans before the first pose left out (the points input places each "
                            "echo in the world by the robot's pose)")


def pose_columns(pose) -> dict:
    """The pose columns of an output row (x, y, theta), empty without a pose."""
    if pose is None:
        return {}
    return {"x": float(pose[0]), "y": float(pose[1]), "theta": float(np.asarray(pose)[2])}


class RowSink:
    """Rows written as they come: CSV to standard output or a file, each flushed; an .npz at the end.

    The columns are the first row's, and the pose columns (x, y, theta) when
    ``pose`` says poses will come; a row without a pose (a scan before the
    pose source's first message) leaves them empty in CSV, NaN in .npz.

    An existing file is never truncated before there is a row to write: a
    CSV file is opened at the first row, an .npz file written whole (beside
    the target, then moved into place) when the rows end. :attr:`rows`
    counts the rows written, for a run that fails midway to say so.
    """

    def __init__(self, out: str | None, pose: bool = False):
        self.out, self.pose = out, pose
        self.npz = out not in (None, "-") and Path(out).suffix.lower() == ".npz"
        self.columns: dict[str, list] = {}
        self.fh = self.writer = None
        self.rows = 0

    def __enter__(self):
        return self

    def write(self, row: dict) -> None:
        if self.pose:
            row = {**row, **{k: row.get(k, math.nan if self.npz else "") for k in ("x", "y", "theta")}}
        if self.npz:
            for key, value in row.items():
                self.columns.setdefault(key, []).append(value)
        else:
            if self.writer is None:
                self.fh = sys.stdout if self.out in (None, "-") else open(self.out, "w", newline="",
                                                                          encoding="utf-8")
                self.writer = csv.DictWriter(self.fh, fieldnames=list(row), lineterminator="\n")
                self.writer.writeheader()
            self.writer.writerow({k: format_cell(v, exact=k == "time") for k, v in row.items()})
            self.fh.flush()
        self.rows += 1

    def __exit__(self, *exc_info):
        if self.npz and self.rows:
            columns = {k: np.asarray(v) for k, v in self.columns.items()}
            write_atomically(self.out, lambda fh: np.savez(fh, **columns))
        if self.fh is not None and self.fh is not sys.stdout:
            self.fh.close()
