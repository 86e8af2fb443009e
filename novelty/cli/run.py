"""``novelty run``: stream a file of scans through a detector, write each scan's novelty."""

from __future__ import annotations

import sys

from ._common import UserError, add_command, parse_params, read_scans, write_novelty

DESCRIPTION = """Stream scans through a detector, as a robot would, learning as it goes.

The novelty of each scan is computed before the scan is learned. Scans are
rows of a CSV (optional header; columns named y, label, distance, run, time
are carried to the output, not used as sensors; a 'time' column gives the
synapses real elapsed time) or the array X of an .npz file. Writes one row a
scan (scan, novelty, ...) to --out (CSV, or .npz by extension; default:
standard output). A batch-only detector is fitted on all the scans, then
scores them."""

EXAMPLES = [
    "novelty run hsom --data scans.csv",
    "novelty run hsom --data scans.csv --param n_rows=5 --param alpha=1.2 --out novelty.csv",
    "novelty run habituating --data corridor-a.npz --param clusterer=som --passes 5 --save a.npz",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "run", "stream scans through a detector and write their novelty",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("detector", metavar="DETECTOR", help="detector name (see 'novelty list detectors')")
    parser.add_argument("--data", required=True, metavar="FILE", help="scans: .csv or .npz")
    parser.add_argument("--param", "-p", action="append", metavar="k=v",
                        help="detector parameter (repeatable); values are JSON-ish: 5, 1.2, true, som")
    parser.add_argument("--passes", type=int, default=1, metavar="N",
                        help="stream the scans N times; the output is the last pass (default 1)")
    parser.add_argument("--out", metavar="FILE", help="novelty per scan: .csv or .npz (default: stdout)")
    parser.add_argument("--save", metavar="MODEL", help="save the trained detector here (.npz model file)")
    return parser


def run(args) -> int:
    from ..bench.suite import DetectorSpec, check_detector

    if args.passes < 1:
        raise UserError(f"--passes must be at least 1; got {args.passes}.")
    det = check_detector(DetectorSpec(args.detector, parse_params(args.param)))
    X, extras = read_scans(args.data)
    if getattr(det, "supports_online", True):
        for i in range(args.passes):
            novelty = det.stream(X, timestamps=extras.get("time") if i == 0 else None)
    else:
        print(f"novelty run: {args.detector} learns in batch only: fitted on all the scans, then scored.",
              file=sys.stderr)
        novelty = det.fit(X).novelty(X)
    write_novelty(args.out, novelty, extras)
    if args.save:
        det.save(args.save)
    if args.out not in (None, "-"):
        print(f"Wrote the novelty of {X.shape[0]} scans to {args.out}"
              + (f"; model saved to {args.save}" if args.save else "") + ".", file=sys.stderr)
    return 0
