"""``novelty simulate``: simulate sonar traversals of an environment."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

from ._common import UserError, add_command

DESCRIPTION = """Simulate a robot's sonar scans along a corridor and write them to a file.

ENV is an environment of the sonar simulator (e.g. paper-a, paper-a-star,
paper-b, paper-c, paper-control). --out takes .npz (every array: X, y,
distance, poses, run) or .csv (sensors, then y and distance)."""

EXAMPLES = [
    "novelty simulate paper-a --out corridor-a.npz",
    "novelty simulate paper-a-star --runs 5 --seed 1 --out a-star.csv",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "simulate", "simulate sonar scans along a corridor",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("environment", metavar="ENV", help="environment name")
    parser.add_argument("--out", required=True, metavar="FILE", help=".npz or .csv")
    parser.add_argument("--runs", type=int, default=1, metavar="N", help="traversals (default 1)")
    parser.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    return parser


def _simulator():
    try:
        module = importlib.import_module("novelty.sonar")
    except ImportError:
        module = None
    simulate = getattr(module, "simulate", None)
    if simulate is None:
        raise UserError("The sonar simulator (novelty.sonar.simulate) is not available in this installation.")
    return simulate


def run(args) -> int:
    if args.runs < 1:
        raise UserError(f"--runs must be at least 1; got {args.runs}.")
    out = Path(args.out)
    if out.suffix.lower() not in (".npz", ".csv"):
        raise UserError(f"--out must end in .npz or .csv; got {args.out}.")
    try:
        data = _simulator()(args.environment, runs=args.runs, seed=args.seed)
    except KeyError as exc:  # an unknown environment, whichever way the simulator says it
        raise UserError(str(exc.args[0]) if exc.args else f"Unknown environment {args.environment!r}.") from None
    if out.suffix.lower() == ".npz":
        data.to_npz(out)
    else:
        data.to_csv(out)
    print(f"Wrote {len(data)} scans of {data.n_sensors} sensors ({args.runs} run(s) of "
          f"{args.environment}, seed {args.seed}) to {out}.", file=sys.stderr)
    return 0
