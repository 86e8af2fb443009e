"""``novelty reproduce``: rerun the paper's experiments in the sonar world; Table 1 beside the paper's."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

try:
    import resource  # the CPU time of the experiments' worker processes (not on Windows)
except ImportError:  # pragma: no cover - depends on the platform
    resource = None

from ._common import UserError, add_command, parse_params

DESCRIPTION = """Rerun the experiments of Marsland, Nehmzow & Shapiro (2000) in the simulated
sonar world and print Table 1 beside the paper's.

The protocol of the paper's section 3.2: pairs of a learning run (L) and a
non-learning run (NL) along corridor A from an untrained filter; then A* (a
door opened), B and C, each from the model learned in A; and the controls, B
and C scored by a filter trained in an open area. Each run is a fresh, seeded
traversal; each learning run saves the model and the next run loads it.

Writes to --out: table1.csv (experiment, trial, mode, integrated, maximum,
paper_integrated, paper_maximum), table1.md, and the paper's figures 4 and 5
as PNG (novelty along the route for every trial, the map's features marked).
"Integrated" is the output summed over the run with the resting activity
(0.0476 a scan for the paper's constants) subtracted.

A has 3 pairs of runs as in Table 1; --settle continues in A until a
non-learning run shows only the resting activity (the paper's rule), and
--a-pairs sets the count. Any registered detector runs the same protocol.

--experiment NAME runs one of the experiments that explain why Table 1 does
not reproduce (table1, synthetic, ablations, sensitivity, maxima; "all"
runs them all), on --n-seeds seeds from --seed, writing NAME.csv, NAME.md
and NAME.png to --out; --report fills the generated blocks of a report
(docs/reproduction.md) with their tables. Options they vary that are not
the paper's are labelled so."""

EXAMPLES = [
    "novelty reproduce",
    "novelty reproduce --seed 3 --out results/seed3",
    "novelty reproduce --detector gwr-novelty --out results/gwr",
    "novelty reproduce --param n_rows=20 --param n_columns=20 --out results/hsom-20x20",
    "novelty reproduce --settle --out results/settled",
    "novelty reproduce --experiment synthetic --out results/experiments",
    "novelty reproduce --experiment all --jobs 2 --out docs/reproduction --report docs/reproduction.md",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "reproduce",
                         "rerun the paper's experiments; print Table 1 beside the paper's, write figures",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("--seed", type=int, default=0, metavar="N",
                        help="seeds the detector and every traversal (default 0)")
    parser.add_argument("--out", default="results/reproduce", metavar="DIR",
                        help="output folder (default results/reproduce)")
    parser.add_argument("--detector", default="hsom", metavar="NAME",
                        help="registered detector (default hsom, the paper's; see 'novelty list detectors')")
    parser.add_argument("--param", "-p", action="append", metavar="k=v",
                        help="detector parameter (repeatable); values are JSON-ish: 5, 1.2, true, som")
    pairs = parser.add_mutually_exclusive_group()
    pairs.add_argument("--a-pairs", type=int, default=3, metavar="N",
                       help="pairs of (L, NL) runs in A (default 3, as in Table 1)")
    pairs.add_argument("--settle", action="store_true",
                       help="continue in A until a non-learning run shows only the resting activity "
                            "(at most --max-a-pairs pairs)")
    parser.add_argument("--max-a-pairs", type=int, default=25, metavar="N",
                        help="most pairs in A with --settle (default 25)")
    parser.add_argument("--control-runs", type=int, metavar="N",
                        help="learning runs of the control filter (default: as many as A had)")
    parser.add_argument("--no-figures", action="store_true", help="write the tables only")
    parser.add_argument("--experiment", metavar="NAME",
                        help="run an explaining experiment instead of the protocol: "
                             "table1, synthetic, ablations, sensitivity, maxima, or all")
    parser.add_argument("--n-seeds", type=int, default=10, metavar="N",
                        help="with --experiment: seeds --seed ... --seed + N - 1 (default 10)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N",
                        help="with --experiment: processes (default 1; results do not depend on it)")
    parser.add_argument("--report", metavar="FILE",
                        help="with --experiment: fill FILE's generated blocks with the tables")
    return parser


def run(args) -> int:
    # deferred: the experiments import the simulator and scikit-learn; `novelty --help` does not
    from .. import reproduce

    for name in ("seed", "a_pairs", "max_a_pairs", "control_runs", "n_seeds", "jobs"):
        value = getattr(args, name)
        minimum = 0 if name == "seed" else 1
        if value is not None and value < minimum:
            raise UserError(f"--{name.replace('_', '-')} must be at least {minimum}; got {value}.")
    if args.experiment is not None:
        return _experiments(args)
    if args.report is not None:
        raise UserError("--report fills a report with the experiments' tables: give --experiment too.")
    params = parse_params(args.param)
    if not args.no_figures:
        _check_matplotlib()
    out = Path(args.out)
    started = time.perf_counter()
    trials = reproduce.run_protocol(args.detector, seed=args.seed, params=params,
                                    control_runs=args.control_runs,
                                    a_pairs=None if args.settle else args.a_pairs,
                                    max_a_pairs=args.max_a_pairs)
    elapsed = time.perf_counter() - started
    rows = reproduce.table1_rows(trials)
    title = _title(args, params)
    print(f"{title}\n")
    print(reproduce.table1_markdown(rows))
    a_pairs = sum(1 for t in trials if t.experiment == "A") // 2
    if args.settle:
        settled = reproduce.is_resting([t for t in trials if t.experiment == "A"][-1])
        state = "settled" if settled else "not settled"
        print(f"\nA: {a_pairs} pairs of runs ({state}; the paper needed 3).")
    out.mkdir(parents=True, exist_ok=True)
    reproduce.write_table1_csv(rows, out / "table1.csv")
    reproduce.write_table1_markdown(rows, out / "table1.md", title)
    written = [out / "table1.csv", out / "table1.md"]
    if not args.no_figures:
        written += reproduce.write_figures(trials, out, note=f" ({args.detector}, seed {args.seed})")
    print(f"\nWrote {', '.join(str(p) for p in written)} ({elapsed:.1f} s).", file=sys.stderr)
    return 0


def _written_by(path: Path, out: Path, names: list[str]) -> bool:
    """Whether ``path`` is one of the files the experiments ``names`` write in ``out``
    (``NAME.csv``, ``NAME.md``, ``NAME.png``, ``NAME-TABLE.csv``)."""
    return (path.resolve().parent == out.resolve()
            and any(path.stem == name or path.stem.startswith(f"{name}-") for name in names))


def _title(args, params: dict) -> str:
    detail = ", ".join([args.detector, f"seed {args.seed}"] + [f"{k}={v}" for k, v in params.items()])
    return (f"Table 1 ({detail}): integrated output above the resting activity and maximum output "
            "of the output neuron, beside Marsland et al. (2000)")


def _check_matplotlib() -> None:
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UserError("The figures need matplotlib (pip install matplotlib), "
                        "or pass --no-figures.") from None


def _experiments(args) -> int:
    # deferred: the experiments import the simulator and scikit-learn; `novelty --help` does not
    from ..reproduce import experiments
    from ..reproduce.experiments import report

    known = experiments.names()
    if args.experiment != "all" and args.experiment not in known:
        raise UserError(f"Unknown experiment {args.experiment!r}; known: {', '.join(known)}, all.")
    if args.report is not None and not Path(args.report).is_file():
        raise UserError(f"--report {args.report}: no such file.")
    names = known if args.experiment == "all" else [args.experiment]
    if args.report is not None and _written_by(Path(args.report), Path(args.out), [*names, "summary"]):
        raise UserError(f"--report {args.report} is a file the experiments write in --out {args.out}: the "
                        "report would be replaced before it is filled. Choose another --out.")
    _check_matplotlib()
    seeds = range(args.seed, args.seed + args.n_seeds)
    blocks: dict[str, str] = {}
    results = {}
    started = time.perf_counter()
    for name in names:
        began, cpu = time.perf_counter(), _cpu_seconds()
        result = results[name] = experiments.run_experiment(name, args.out, seeds=seeds, jobs=args.jobs,
                                                            progress=sys.stderr)
        blocks.update(result.blocks())
        print(f"## {result.title}\n\n" + "\n".join(result.blocks().values()))
        print(f"({name}: {time.perf_counter() - began:.1f} s, CPU {_cpu_seconds() - cpu:.1f} s)\n",
              file=sys.stderr)
    if args.experiment == "all":
        blocks["summary"] = experiments.write_summary(results, args.out)
        print(f"## Summary\n\n{blocks['summary']}")
    elapsed = time.perf_counter() - started
    if args.report is not None:
        blocks["command"] = (f"`novelty reproduce --experiment {args.experiment} --seed {args.seed} "
                             f"--n-seeds {args.n_seeds} --jobs {args.jobs} --out {args.out} "
                             f"--report {args.report}` ran in {elapsed:.0f} s{_load()}.\n")
        report.fill_file(args.report, blocks, partial=args.experiment != "all")
    print(f"Wrote {args.out} ({elapsed:.1f} s).", file=sys.stderr)
    return 0


def _cpu_seconds() -> float:
    """CPU time (s) of this process and of its finished workers; NaN where unknown."""
    if resource is None:
        return float("nan")
    return sum(getattr(resource.getrusage(who), field) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
               for field in ("ru_utime", "ru_stime"))


def _load() -> str:
    """CPU time of this process and its workers, and the machine's load, for the report."""
    if resource is None or not hasattr(os, "getloadavg"):
        return ""
    return (f" of wall-clock time and {_cpu_seconds():.0f} s of CPU time (this process and its workers) on "
            f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}")
