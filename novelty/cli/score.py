"""``novelty score``: score scans with a saved detector, without learning."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from .. import load
from ..answers import PAPER
from .._atomic import check_target
from ._common import UserError, add_command, add_data_options, check_layout, check_outputs, read_scans, write_novelty
from .familiar import add_calibration_options, p_values, say_calibration, stretch_of, threshold_in_force
from .recording_options import (RowSink, add_recording_options, check_recording_options, is_recording, pose_columns,
                        recording_scans)

DESCRIPTION = """Score scans with a saved model, without learning anything.

The model is a file written by 'novelty run --save' or detector.save(path).
Scans are read as 'novelty run' reads them: a CSV or .npz file (the same
column options), or a robot recording (a CARMEN log, .log or .log.gz; a ROS
bag, .bag, .db3 or .mcap; the same recording options). The output is one row
a scan: scan, novelty, alarm (novelty above the model's threshold), threshold,
p_value when the model is calibrated, and the carried columns (a recording's
time and pose).

For alarms at a stated rate, --calibrate names a stretch the robot knows
(seconds or rows of --data, or a recording of its own) and --false-alarm-rate
the rate: the stretch is scored as everything here is, frozen, and the
threshold set so that familiar scans raise alarms at most at that rate
(split-conformal); --save keeps the calibrated model."""

#: a model of the paper's detector on the paper's sonar; on recordings, one of the answer of "Which
#: detector?" to learning a clean area and flagging what differs (novelty.answers.FROZEN), learned by
#: 'novelty run {FROZEN} --data monday.log.gz --save monday.npz'
EXAMPLES = [
    f"novelty score --model {PAPER}.npz --data new-scans.csv",
    f"novelty score --model {PAPER}.npz --data corridor-b.npz --out novelty-b.csv",
    "novelty score --model monday.npz --data tuesday.log.gz --calibrate 0:300 --false-alarm-rate 0.01 "
    "--out alarms.csv",
    "novelty score --model monday.npz --data run.bag --topic /scan --calibrate lap2.bag --save calibrated.npz",
    "novelty score --model calibrated.npz --data wednesday.bag --topic /scan --out wednesday.csv",
    "novelty score --model monday.npz --data held-out.csv --calibrate rows:0:200 --false-alarm-rate 0.05",
]

#: rows of a recording scored in one call (the scoring of a batch is one pass over the model)
_BATCH = 256


def add_parser(subparsers):
    parser = add_command(subparsers, "score", "score scans with a saved model (no learning)",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("--model", required=True, metavar="FILE", help="a saved detector (.npz)")
    add_data_options(parser, "scans: .csv or .npz, or a recording (.log, .log.gz, .bag, .db3, .mcap)")
    add_recording_options(parser)
    add_calibration_options(parser, "scored frozen by the model")
    parser.add_argument("--out", metavar="FILE", help="novelty per scan: .csv or .npz (default: stdout)")
    parser.add_argument("--save", metavar="MODEL", help="write the model, calibrated, here (.npz model file)")
    return parser


def run(args) -> int:
    stretch = stretch_of(args)
    check_outputs([("--model", args.model), ("--data", args.data), ("--calibrate", stretch and stretch.path)],
                  [("--out", args.out), ("--save", args.save)])
    if not Path(args.model).is_file():
        raise UserError(f"Model file not found: {args.model}")
    if args.save:
        if stretch is None:
            raise UserError("--save writes the calibrated model: give --calibrate too (novelty score learns nothing).")
        check_target(args.save)
    if args.data == "-":
        raise UserError("novelty score reads a file or a recording, not standard input; 'novelty run --data -' "
                        "scores a live stream.")
    det = load(args.model)
    if is_recording(args.data):
        n = _score_recording(det, args, stretch)
    else:
        n = _score_file(det, args, stretch)
    if args.save:
        det.save(args.save)
    if args.out not in (None, "-"):
        print(f"Wrote the novelty of {n} scans to {args.out}"
              + (f"; calibrated model saved to {args.save}" if args.save else "") + ".", file=sys.stderr)
    return 0


def _score_file(det, args, stretch) -> int:
    data = read_scans(args)
    check_layout(det, data, "The model")
    novelty = det.novelty(data.X)
    if stretch is not None:
        if stretch.path is not None:
            familiar = _familiar_scans(det, args, stretch.path)
        else:
            time = data.columns.get("time")
            elapsed = None if time is None else np.asarray(time, dtype=np.float64) - float(time[0])
            inside = np.array([stretch.holds(i, None if elapsed is None else elapsed[i]) for i in range(len(data))])
            if not inside.any():
                raise UserError(f"--calibrate {stretch.text}: no scan of {args.data} lies in it.")
            familiar = data.X[inside]
        det.calibrate(familiar, args.false_alarm_rate, source=stretch.describe(args.data))
        say_calibration(det, "novelty score")
    threshold = threshold_in_force(det, "novelty score")
    alarm = None if threshold is None else (novelty > threshold).astype(np.int8)
    extra = {} if threshold is None else {"threshold": np.full(novelty.size, threshold)}
    p = p_values(det, novelty)
    write_novelty(args.out, novelty, data, alarm, extra=extra if p is None else {**extra, "p_value": p})
    return len(data)


def _score_recording(det, args, stretch) -> int:
    """Score a recording's scans frozen (a batch at a time), calibrate, then write a row a scan."""
    from ..io.bags.read_report import ReadReport  # deferred: the readers are loaded only for a recording

    check_recording_options(args)
    report = ReadReport()
    times, poses, novelty, familiar, batch = [], [], [], [], []
    first = None
    for n, (time, x, pose) in enumerate(recording_scans(args, det, report)):
        first = time if first is None else first
        times.append(time)
        poses.append(pose)
        batch.append(x)
        if stretch is not None and stretch.path is None and stretch.holds(n, None if time is None else time - first):
            familiar.append(x)
        if len(batch) == _BATCH:
            novelty.append(det.novelty(np.array(batch)))
            batch = []
    if batch:
        novelty.append(det.novelty(np.array(batch)))
    for line in report.lines():
        print(f"novelty score: {line}", file=sys.stderr)
    if not times:
        raise UserError(f"No scans in {args.data}: its messages made no whole scan.")
    novelty = np.concatenate(novelty)
    if stretch is not None:
        if stretch.path is not None:
            familiar = _familiar_scans(det, args, stretch.path)
        elif not familiar:
            raise UserError(f"--calibrate {stretch.text}: no scan of {args.data} lies in it.")
        det.calibrate(np.array(familiar), args.false_alarm_rate, source=stretch.describe(args.data))
        say_calibration(det, "novelty score")
    threshold = threshold_in_force(det, "novelty score")
    p = p_values(det, novelty)
    with RowSink(args.out, pose=any(pose is not None for pose in poses)) as sink:
        for n, value in enumerate(novelty):
            row = {"scan": n, "novelty": float(value)}
            if threshold is not None:
                row.update(alarm=int(value > threshold), threshold=threshold)
            if p is not None:
                row["p_value"] = float(p[n])
            sink.write({**row, "time": times[n], **pose_columns(poses[n])})
    return len(times)


def _familiar_scans(det, args, path: str) -> np.ndarray:
    """The scans of the familiar file or recording ``path``, read with the options of ``--data``."""
    familiar = argparse.Namespace(**{**vars(args), "data": path})
    if not is_recording(path):
        return read_scans(familiar).X
    check_recording_options(familiar)
    scans = [x for _, x, _ in recording_scans(familiar, det)]
    if not scans:
        raise UserError(f"--calibrate {path}: its messages made no whole scan.")
    return np.array(scans)
