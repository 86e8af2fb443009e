"""``novelty run``: stream scans through a detector, write each scan's novelty."""

from __future__ import annotations

import csv
import sys

import numpy as np

from .._atomic import check_target
from .._validation import pass_timestamps
from ..alarms import ALARM_FORMS, Alarm, parse_alarm
from ._common import UserError, add_command, add_data_options, check_outputs, format_cell, one_line, parse_params, \
    read_scans, write_novelty
from .recording import RowSink, add_recording_options, pose_columns, recording_points, recording_rings

DESCRIPTION = """Stream scans through a detector, as a robot would, learning as it goes.

The novelty of each scan is computed before the scan is learned; the alarm
is 1 where the novelty is above the detector's threshold (--param
threshold=...), as predict() says -1, or where the --alarm policy is
raised (k of the last n scans, hysteresis). Scans are rows of a CSV
(optional header) or the array X of an .npz file; --columns chooses the
sensors, and columns named y/label, distance, run, time are carried to the
output, not used as sensors (a time column gives the synapses real elapsed
time; with --passes, each pass starts one typical step after the previous
ended). Writes one row a scan (scan, novelty, alarm, ...) to --out (CSV, or
.npz by extension; default: standard output). A batch-only detector is
fitted on all the scans, then scores them.

With --data - the scans are read from standard input, a CSV line at a time
(a header line first, or none), and each scan's row is written and flushed
as soon as it is scored: for a live sensor feed.

A robot recording (a CARMEN log, .log or .log.gz; a ROS 1 bag, .bag; a ROS 2
bag, .db3 or .mcap) is read a message at a time: each laser scan (its
fragments assembled into a whole revolution, its beams placed through its
mount in the tf tree or --mount, several lasers merged) reduced to --sectors
sectors seen from the robot's centre (or each ring of sonar Range readings),
preprocessed as the paper's (1 - min(r, T) / T), scored, learned, and its
row (scan, novelty, alarm, time, x, y, theta: the base frame's pose at the
scan's time) written and flushed at once. A detector that reads the robot's
pose with each scan (map-explore, habituating-map) gets the points input
instead: the pose, each sector's nearness and its end point in the world,
180 sectors unless --sectors says (one a beam for a sensor of fewer). What the reading found (scans
assembled, base frame, mounts, poses) is said on standard error. A run that
fails leaves an existing --out as it was, or (midway) keeps the rows written;
an --out or --save naming the file --data names (or each other's) is refused
before anything is read."""

EXAMPLES = [
    "novelty run hsom --data scans.csv",
    "novelty run hsom --data scans.csv --param n_rows=5 --param alpha=1.2 --out novelty.csv",
    "novelty run habituating --data corridor-a.npz --param clusterer=som --passes 5 --save a.npz",
    "novelty run hsom --data ranges.csv --columns 'sonar*' --preprocess paper --time stamp",
    "rostopic echo -p /sonar | novelty run hsom --data - --columns 'field.ranges*' --preprocess paper",
    "novelty run hsom --data scans.csv --alarm k-of-n:3,5",
    "novelty run hsom --data run.bag --topic /scan --sectors 16 --pose-topic /odom --out novelty.csv",
    "novelty run hsom --data intel-corrected.log.gz --sectors 16 --reduce min",
    "novelty run hsom --data robot.bag --topic /scan_front,/scan_rear --mount /scan_rear=-0.3,0,180",
    "novelty run map-explore --data run.bag --topic /scan --pose-topic /odom --out novelty.csv",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "run", "stream scans through a detector and write their novelty",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("detector", metavar="DETECTOR", help="detector name (see 'novelty list detectors')")
    add_data_options(parser, "scans: .csv or .npz, - for CSV lines on standard input, or a recording "
                     "(.log, .log.gz, .bag, .db3, .mcap)")
    add_recording_options(parser)
    parser.add_argument("--param", "-p", action="append", metavar="k=v",
                        help="detector parameter (repeatable); values are JSON-ish: 5, 1.2, true, som")
    parser.add_argument("--passes", type=int, default=1, metavar="N",
                        help="stream the scans N times; the output is the last pass (default 1)")
    parser.add_argument("--out", metavar="FILE", help="novelty per scan: .csv or .npz (default: stdout)")
    parser.add_argument("--save", metavar="MODEL", help="save the trained detector here (.npz model file)")
    parser.add_argument("--alarm", metavar="POLICY",
                        help="when the alarm column is 1: " + ", ".join(ALARM_FORMS) + " (T defaults to the "
                        "detector's threshold; k-of-n: K of the last N scans above T; hysteresis: raised "
                        "above HIGH until below LOW). Default: threshold")
    return parser


def run(args) -> int:
    # deferred: the benchmark imports scikit-learn; `novelty --help` does not
    from ..bench.spec_checks import check_detector
    from ..bench.specs import DetectorSpec

    if args.passes < 1:
        raise UserError(f"--passes must be at least 1; got {args.passes}.")
    check_outputs([("--data", args.data)], [("--out", args.out), ("--save", args.save)])
    if args.save:
        check_target(args.save)  # a device or a pipe is refused before the scans are read
    det = check_detector(DetectorSpec(args.detector, parse_params(args.param)))
    alarm = _alarm_policy(det, args.alarm)
    if args.data == "-":
        n = _run_stream(det, args, alarm)
    elif _is_recording(args.data):
        n = _run_recording(det, args, alarm)
    else:
        n = _run_file(det, args, alarm)
    if args.save:
        det.save(args.save)
    if args.out not in (None, "-"):
        print(f"Wrote the novelty of {n} scans to {args.out}"
              + (f"; model saved to {args.save}" if args.save else "") + ".", file=sys.stderr)
    return 0


def _alarm_policy(det, spec: str | None) -> Alarm | None:
    """The --alarm policy, its threshold the detector's; None for a detector without a threshold."""
    threshold = getattr(det, "threshold", None)
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.floating)):
        threshold = None
    if spec is None and threshold is None:
        return None
    try:
        return parse_alarm(spec or "threshold", threshold)
    except ValueError as exc:
        raise UserError(f"--alarm: {exc}") from None


def _run_file(det, args, alarm: Alarm | None) -> int:
    data = read_scans(args)
    timestamps = data.columns.get("time")
    if getattr(det, "supports_online", True):
        for i in range(args.passes):
            clock = None if timestamps is None else pass_timestamps(timestamps, i)
            novelty = det.stream(data.X, timestamps=clock)
    else:
        print(f"novelty run: {args.detector} learns in batch only: fitted on all the scans, then scored.",
              file=sys.stderr)
        novelty = det.fit(data.X).novelty(data.X)
    write_novelty(args.out, novelty, data, None if alarm is None else alarm.run(novelty).astype(np.int8))
    return len(data)


def _is_recording(path: str) -> bool:
    # deferred: the readers are loaded only for a recording
    from ..io.recording.readers import is_recording

    return is_recording(path)


def _run_recording(det, args, alarm: Alarm | None) -> int:
    """Score and learn a recording's rings as they are read, writing each ring's row at once."""
    # deferred: the readers are loaded only for a recording
    from ..io.bags.report import ReadReport

    if not getattr(det, "supports_online", True):
        raise UserError(f"{args.detector} learns in batch only; it cannot stream a recording.")
    if args.passes != 1 or args.bin_length is not None or args.columns or args.preprocess != "none":
        raise UserError("A recording is read as it streams: no --passes, --bin-length, --columns or "
                        "--preprocess (its rings are preprocessed as the paper's; --range-threshold sets T).")
    report = ReadReport()
    # a detector that reads the robot's pose with each scan (the habituating maps) gets the points input
    read = recording_points if getattr(det, "input_layout", None) == "points" else recording_rings
    with RowSink(args.out, pose=args.pose_topic is not None) as sink:
        try:
            for n, (time, x, pose) in enumerate(read(args, report)):
                sink.pose = sink.pose or report.has_poses   # known once the reading has begun
                novelty = det.score_learn_one(x, time if args.stamps else None)
                row = {"scan": n, "novelty": novelty}
                if alarm is not None:
                    row["alarm"] = int(alarm.update(novelty))
                sink.write({**row, "time": time, **pose_columns(pose)})
        except (UserError, ValueError, OSError) as exc:
            if not sink.rows:
                raise
            # the rows scored so far are kept: say how many, and where
            where = "standard output" if args.out in (None, "-") else args.out
            raise UserError(f"{one_line(exc)} (the first {sink.rows} scans' rows were written to {where} "
                            "before it)") from None
    for line in report.lines():
        print(f"novelty run: {line}", file=sys.stderr)
    if sink.rows == 0:
        raise UserError(f"No scans in {args.data}: its messages made no whole scan.")
    return sink.rows


def _run_stream(det, args, alarm: Alarm | None) -> int:
    """Score and learn standard input a line at a time, writing each scan's row at once."""
    if not getattr(det, "supports_online", True):
        raise UserError(f"{args.detector} learns in batch only; it cannot score a stream (--data -).")
    if args.passes != 1 or args.bin_length is not None:
        raise UserError("--passes and --bin-length need the whole file; not with --data -.")
    if args.out not in (None, "-"):
        raise UserError("With --data - the novelty goes to standard output (no --out).")
    # deferred: `novelty --help` does not read files
    from ..io.tables.stream import StreamReader

    scans = StreamReader(sys.stdin, columns=args.columns, label=args.label, time=args.time,
                         preprocess=args.preprocess, threshold=args.range_threshold)
    writer = None
    n = 0
    for x, extras in _checked(scans):
        novelty = det.score_learn_one(x, extras.get("time"))
        row = {"scan": n, "novelty": novelty}
        if alarm is not None:
            row["alarm"] = int(alarm.update(novelty))
        row.update(extras)
        if writer is None:
            writer = csv.DictWriter(sys.stdout, fieldnames=list(row), lineterminator="\n")
            writer.writeheader()
        writer.writerow({k: format_cell(v, exact=k == "time") for k, v in row.items()})
        sys.stdout.flush()
        n += 1
    if n == 0:
        raise UserError("No scans on standard input.")
    return n


def _checked(scans):
    """The scans of a stream, a line that cannot be read a :class:`UserError` (its message, no traceback)."""
    try:
        yield from scans
    except ValueError as exc:
        raise UserError(str(exc)) from None
