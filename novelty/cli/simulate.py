"""``novelty simulate``: simulate sonar traversals of an environment.

Shares its name with ``novelty/sonar/simulate.py``: the simulator, and the command that runs it (a
command's module is named after the command).
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

from .. import datasets
from .._markup import counted
from ._common import UserError, add_command

DESCRIPTION = """Simulate a robot's sonar scans along a corridor and write them to a file.

ENV is an environment of the sonar simulator (paper-a, paper-a-star,
paper-b, paper-c, paper-control), or any simulated task of the dataset
registry (e.g. inspection-easy, paper-a-to-a-star: training and test scans
with their labels; --runs does not apply). --out takes .npz (X and every
per-scan array: y, split, distance, poses, run, feature ids, metadata) or
.csv (sensors, then the per-scan ground truth)."""

EXAMPLES = [
    "novelty simulate paper-a --out corridor-a.npz",
    "novelty simulate paper-a-star --runs 5 --seed 1 --out a-star.csv",
    "novelty simulate inspection-hard --seed 3 --out inspection.csv",
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


def _task(args):
    """A registered task of that name, built with the seed, or None."""
    if args.environment not in datasets.registry:
        return None
    accepted = datasets.registry.parameters(args.environment)
    options = {"seed": args.seed} if accepted is None or "seed" in accepted else {}
    return datasets.load(args.environment, **options)


def run(args) -> int:
    if args.runs < 1:
        raise UserError(f"--runs must be at least 1; got {args.runs}.")
    out = Path(args.out)
    if out.suffix.lower() not in (".npz", ".csv"):
        raise UserError(f"--out must end in .npz or .csv; got {args.out}.")
    try:
        data = _simulator()(args.environment, runs=args.runs, seed=args.seed)
    except (KeyError, ValueError) as exc:  # not an environment: perhaps a registered task
        data = _task(args)
        if data is None:
            raise UserError(str(exc.args[0]) if exc.args else f"Unknown environment {args.environment!r}.") from None
    if out.suffix.lower() == ".npz":
        data.to_npz(out)
    else:
        data.to_csv(out)
    what = f"{counted(args.runs, 'run')} of " if data.split is None else "task "
    print(f"Wrote {len(data)} scans of {data.n_sensors} sensors ({what}{args.environment}, "
          f"seed {args.seed}) to {out}.", file=sys.stderr)
    return 0
