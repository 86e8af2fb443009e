"""``novelty bench``: run a benchmark suite and print what a reader needs first (the rest in summary.md)."""

from __future__ import annotations

import os
import shlex
import sys

from pathlib import Path

from .._atomic import inside, same_file
from .._markup import counted
from ._common import UserError, add_command

DESCRIPTION = """Run detectors x tasks x seeds and rank the detectors.

Each cell streams the task's training scans through the detector (as many
passes as the task says), sets an alarm threshold from the training novelty,
then scores the test scans without learning. The terminal shows the
detectors ranked by ROC AUC with the columns to read first, what each means,
and a verdict; everything goes to --out: results.csv and results.jsonl (one
row a cell, with provenance), summary.md (every metric,
the ranking; each detector paired with a reference detector task by task,
the seeds of a task averaged first; ranks per task; Friedman, Wilcoxon-Holm
and Bayesian signed-rank tests over tasks, or why too few tasks allow no
claim; the command and versions) and plots/ (with a critical-difference
diagram). --compare-on-task TASK adds a paired bootstrap over that task's
test scans (on an exploration task, an interval over its seeds' worlds);
--reference prints the paired comparison too. Name your tasks with name=
(--task 'files path=a.csv name=lab-a'). Rerunning the same command
resumes: finished cells are skipped, except those whose detector or task
resolves to something else now (a preset or task changed since): these are
recomputed, and the run says how many. A cell that fails -- an error, a worker
process that dies, a cell past --cell-timeout -- is recorded as failed and
the run goes on; a rerun tries failed cells again. A suite is a TOML file (see
benchmarks/suites/ in the source tree), the embedded --quick suite, or
--detector/--task options. Your own scans are the task 'files' (--task 'files
path=scans.csv ...' or a suite's [[tasks]] path = "scans.csv"; see 'novelty
list datasets'). The exit code is 1 if every cell failed. With --protocol
exploration (or a suite's protocol = "exploration") every scan is scored, then
learned, in order, and the table says which detectors flag a feature on first
sight and habituate to it as it recurs."""

EXAMPLES = [
    "novelty bench --quick --out results/quick",
    "novelty bench benchmarks/suites/habituation.toml --out results/habituation --jobs 2",
    "novelty bench suite.toml --out results --backend dask --scheduler tcp://10.0.0.5:8786",
    "novelty bench benchmarks/suites/exploration.toml --out results/exploration --jobs 2",
    "novelty bench --protocol exploration --detector gwr-novelty --detector river-hst "
    "--task exploration-open-door --seeds 2 --out results/explore",
    "novelty bench --detector hsom --detector 'habituating clusterer=som n_rows=5' "
    "--task inspection-easy --seeds 0,1,2 --out results/mine",
    "novelty bench --detector hsom --detector lof "
    "--task 'files path=scans.csv label=novel train_rows=200' --out results/mine",
    "novelty bench --detector kmeans-stanley --detector parzen --task 'files path=a.csv name=lab-a "
    "label=novel train_rows=200' --task 'files path=b.csv name=lab-b label=novel train_rows=200' "
    "--seeds 3 --compare-on-task lab-a --out results/two-labs",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "bench", "run a benchmark suite (detectors x tasks x seeds)",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("suite", nargs="?", metavar="SUITE.toml", help="suite file")
    parser.add_argument("--out", metavar="DIR", default="novelty-bench",
                        help="output folder (default: ./novelty-bench)")
    parser.add_argument("--quick", action="store_true",
                        help="the embedded default suite: the recommended detectors, the paper's and "
                        "baselines, 10 x 2 tasks x 2 seeds; slower the first time, as numba "
                        "compiles and caches its kernels")
    parser.add_argument("--detector", action="append", metavar="'NAME [k=v ...]'",
                        help="a detector with its parameters (repeatable; replaces the suite's)")
    parser.add_argument("--task", action="append", metavar="'NAME [k=v ...]'",
                        help="a task with its options (repeatable; replaces the suite's)")
    parser.add_argument("--seeds", metavar="N|S,S,..",
                        help="a count N >= 1 (seeds 0 to N-1) or a list with commas: '0,1,2', "
                        "or '5,' for seed 5 alone")
    parser.add_argument("--reference", metavar="NAME",
                        help="the detector (its label in the table) each other is paired with, cell by "
                        "cell (default: the suite's 'reference', else its first detector)")
    parser.add_argument("--compare-on-task", action="append", metavar="TASK", default=[],
                        help="compare each detector with the reference on this task alone: a paired "
                        "bootstrap over its test scans (ROC AUC and AP intervals), and the corrected "
                        "resampled t-test over seeds that draw different splits; on an exploration "
                        "task, the mean difference of first-encounter AUC over seeds that build their "
                        "own worlds, with its Student-t interval (repeatable; a hold-out run of one "
                        "task gets it anyway)")
    parser.add_argument("--threshold", metavar="max|Q",
                        help="alarm threshold: 'max' of the training novelty, or a quantile Q in (0, 1]")
    parser.add_argument("--protocol", choices=("holdout", "exploration"),
                        help="holdout (train, freeze, score the test part) or exploration (every "
                        "scan scored, then learned, in order); default: the suite's, else holdout")
    parser.add_argument("--jobs", "-j", type=int, default=1, metavar="N",
                        help="cells run at once (processes or Dask workers; default 1)")
    parser.add_argument("--backend", choices=("serial", "joblib", "dask"),
                        help="serial, joblib (processes on this machine) or dask "
                        "(default: serial, joblib with --jobs > 1, dask with --scheduler)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="Dask scheduler address (default with --backend dask: a local cluster)")
    parser.add_argument("--cell-timeout", type=float, metavar="SECONDS",
                        help="stop a cell that runs longer and record it as failed (cells then run "
                        "in worker processes, serial runs in one); overrides the suite's cell_timeout")
    parser.add_argument("--no-plots", action="store_true", help="do not draw plots")
    parser.add_argument("--no-memory", action="store_true",
                        help="skip the peak-memory measurement (a second, traced run of each cell)")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress output")
    return parser


def build_suite(args):
    """The suite the options describe (file, --quick, and command-line overrides)."""
    # deferred: the benchmark imports scikit-learn; `novelty --help` does not
    from ..bench import Suite, load_suite, quick_suite_path
    from ..bench.specs import detector_from_text, parse_seeds, parse_value, tasks_from_text

    if args.suite and args.quick:
        raise UserError("Give either a suite file or --quick, not both.")
    if args.suite or args.quick:
        suite = load_suite(args.suite or quick_suite_path())
    elif args.detector and args.task:
        suite = Suite([], [], name="command line")
    else:
        raise UserError("Nothing to run: give a suite file, --quick, or both --detector and --task.")
    if args.detector:
        suite.detectors = [detector_from_text(t) for t in args.detector]
    if args.task:
        suite.tasks = [task for text in args.task for task in tasks_from_text(text)]
    if args.seeds:
        suite.seeds = parse_seeds(args.seeds, "--seeds")
    if args.threshold:
        suite.threshold = parse_value(args.threshold)
    if args.protocol:
        suite.protocol = args.protocol
    if args.no_memory:
        suite.memory = False
    if args.reference:
        suite.reference = args.reference
    if args.cell_timeout is not None:
        suite.cell_timeout = args.cell_timeout
    return suite.check()


#: what a bench writes in --out: files it replaces, and folders it writes files in
WRITTEN_FILES, WRITTEN_FOLDERS = ("results.csv", "results.jsonl", "summary.md"), ("cells", "plots")


def _check_inputs_kept(args, suite) -> None:
    """Refuse a suite or a task's file among what the bench writes in --out, before anything is run."""
    # deferred: the benchmark imports scikit-learn; `novelty --help` does not
    from ..bench.specs import FILE_OPTIONS, FILES_TASK, RECORDING_FILE_OPTIONS

    out = Path(args.out)
    reads = [("the suite", args.suite)] if args.suite else []
    for task in suite.tasks:
        named = FILE_OPTIONS if task.name == FILES_TASK else RECORDING_FILE_OPTIONS.get(task.name, ())
        for key in named:
            value = task.options.get(key)
            names = value.split(",") if isinstance(value, str) else value if isinstance(value, list) else []
            reads += [(f"task {task.label}'s {key}", name.strip()) for name in names if isinstance(name, str)]
    for what, path in reads:
        if any(same_file(path, out / name) for name in WRITTEN_FILES) or any(
                inside(path, out / folder) for folder in WRITTEN_FOLDERS):
            raise UserError(f"{what} {path} is among the files novelty bench writes in --out {out} "
                            f"({', '.join(WRITTEN_FILES)}, {'/, '.join(WRITTEN_FOLDERS)}/): writing them would "
                            "replace what is read. Choose another --out, or move the file.")


def _print_results(report, paired: bool) -> None:
    """A hold-out run: the table a reader needs first, what its columns mean, a verdict (and the paired
    comparison when ``paired``: --reference was given); an exploration run: its table and the tests."""
    # deferred: the benchmark imports scikit-learn; `novelty --help` does not
    from ..bench.reports.statistics import paired_text, statistics_line
    from ._bench_table import columns_in_words, first_table, verdict

    if report.protocol == "holdout" and report.rows:
        print(first_table(report.rows))
        print(f"\n{columns_in_words(report.rows)}")
        if paired:
            print("\n" + paired_text(report.rows, report.reference))
        print("\n" + verdict(report.rows))
    else:
        print(report.table)
        if report.rows:
            print("\n" + statistics_line(report.rows))
    if report.comparisons:
        print("\n".join(report.comparisons))
    for note in report.notes:
        print(note)


def run(args) -> int:
    # deferred: the benchmark imports scikit-learn; `novelty --help` does not
    from ..bench.benchmark import run_suite

    if args.jobs < 1:
        raise UserError(f"--jobs must be at least 1; got {args.jobs}.")
    backend = args.backend or ("dask" if args.scheduler else "joblib" if args.jobs > 1 else "serial")
    if args.scheduler and backend != "dask":
        raise UserError("--scheduler is for --backend dask.")
    suite = build_suite(args)
    _check_inputs_kept(args, suite)
    n_cells = len(suite.detectors) * len(suite.tasks) * len(suite.seeds)
    if not args.quiet:
        print(f"Suite {suite.name!r}: {counted(len(suite.detectors), 'detector')} x "
              f"{counted(len(suite.tasks), 'task')} x {counted(len(suite.seeds), 'seed')} = "
              f"{counted(n_cells, 'cell')}, backend {backend}"
              + (f" ({args.jobs} jobs)" if backend != "serial" else "") + ".", file=sys.stderr)
    unknown = [t for t in args.compare_on_task if t not in {task.label for task in suite.tasks}]
    if unknown:
        raise UserError(f"--compare-on-task {unknown[0]!r} is not a task of this run; tasks: "
                        f"{', '.join(task.label for task in suite.tasks)}.")
    results = run_suite(suite, args.out, backend=backend, jobs=args.jobs, scheduler=args.scheduler,
                        plots=not args.no_plots, quiet=args.quiet, compare_on=args.compare_on_task,
                        command=shlex.join(["novelty", *getattr(args, "_argv", ["bench"])]))
    report = results.report
    summary = os.path.join(args.out, "summary.md")
    _print_results(report, paired=args.reference is not None)
    if report.failed:
        print(f"{report.failed} of {counted(len(report.rows), 'cell')} failed; their errors are in {summary}.")
    plots = os.path.join(args.out, "plots", "") if any(p.suffix == ".png" for p in report.files) else None
    print(f"The rest (every metric, the paired comparison, ranks per task and the tests between detectors) "
          f"is in {summary}" + (f"; plots in {plots}" if plots else "") + f"; each cell in "
          f"{os.path.join(args.out, 'results.csv')} (and results.jsonl).")
    if report.interrupted:
        print("Interrupted: rerun the same command to resume.", file=sys.stderr)
        return 130
    if report.rows and report.failed == len(report.rows):
        first = next(r.get("error", "") for r in report.rows)
        print(f"novelty bench: every cell failed ({report.failed} of {report.failed}), nothing was "
              f"measured; the first error: {first} (all errors in {summary}).", file=sys.stderr)
        return 1
    return 0
