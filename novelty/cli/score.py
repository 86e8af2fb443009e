"""``novelty score``: score scans with a saved detector, without learning."""

from __future__ import annotations

import sys
from pathlib import Path

from .. import load
from ._common import UserError, add_command, add_data_options, alarms, check_outputs, read_scans, write_novelty

DESCRIPTION = """Score scans with a saved model, without learning anything.

The model is a file written by 'novelty run --save' or detector.save(path).
Scans are read as for 'novelty run' (the same column options); the output
is one row a scan: scan, novelty, alarm (novelty above the model's
threshold) and the carried columns."""

EXAMPLES = [
    "novelty score --model hsom.npz --data new-scans.csv",
    "novelty score --model hsom.npz --data corridor-b.npz --out novelty-b.csv",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "score", "score scans with a saved model (no learning)",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("--model", required=True, metavar="FILE", help="a saved detector (.npz)")
    add_data_options(parser)
    parser.add_argument("--out", metavar="FILE", help="novelty per scan: .csv or .npz (default: stdout)")
    return parser


def run(args) -> int:
    check_outputs([("--model", args.model), ("--data", args.data)], [("--out", args.out)])
    if not Path(args.model).is_file():
        raise UserError(f"Model file not found: {args.model}")
    det = load(args.model)
    data = read_scans(args)
    novelty = det.novelty(data.X)
    write_novelty(args.out, novelty, data, alarms(det, novelty))
    if args.out not in (None, "-"):
        print(f"Wrote the novelty of {len(data)} scans to {args.out}.", file=sys.stderr)
    return 0
