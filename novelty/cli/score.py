"""``novelty score``: score scans with a saved detector, without learning."""

from __future__ import annotations

import sys

from ._common import add_command, read_scans, write_novelty

DESCRIPTION = """Score scans with a saved model, without learning anything.

The model is a file written by 'novelty run --save' or detector.save(path).
Scans are read as for 'novelty run'; the output is one row a scan."""

EXAMPLES = [
    "novelty score --model hsom.npz --data new-scans.csv",
    "novelty score --model hsom.npz --data corridor-b.npz --out novelty-b.csv",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "score", "score scans with a saved model (no learning)",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("--model", required=True, metavar="FILE", help="a saved detector (.npz)")
    parser.add_argument("--data", required=True, metavar="FILE", help="scans: .csv or .npz")
    parser.add_argument("--out", metavar="FILE", help="novelty per scan: .csv or .npz (default: stdout)")
    return parser


def run(args) -> int:
    from pathlib import Path

    from .. import load
    from ._common import UserError

    if not Path(args.model).is_file():
        raise UserError(f"Model file not found: {args.model}")
    det = load(args.model)
    X, extras = read_scans(args.data)
    write_novelty(args.out, det.novelty(X), extras)
    if args.out not in (None, "-"):
        print(f"Wrote the novelty of {X.shape[0]} scans to {args.out}.", file=sys.stderr)
    return 0
