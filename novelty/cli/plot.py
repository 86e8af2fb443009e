"""``novelty plot``: novelty along the route, from a benchmark or a 'novelty run' output."""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

from .._atomic import not_regular
from ._common import UserError, add_command, check_outputs

DESCRIPTION = """Plot the novelty along the route.

RESULTS is either the output folder of 'novelty bench' (or its results.jsonl
or results.csv): one panel a detector, for one task and seed, with the novel
scans shaded and the alarm threshold dashed; or the output of 'novelty run' /
'novelty score' (.csv or .npz with a 'novelty' column, and optionally
'distance', 'y' (1 for a novel scan), 'alarm' and 'run'): the novelty along
the route, each alarm marked and each run's start drawn. A recording's output
(columns 'x' and 'y': the robot's position) is drawn on the robot's path
too; a file with 'x' but no 'y' has no path, and is drawn along the scans."""

EXAMPLES = [
    "novelty plot novelty.csv --out route.png",
    "novelty run hsom --data intel-corrected.log.gz --out intel.csv && novelty plot intel.csv --out path.png",
    "novelty plot results/quick --task inspection-easy --seed 0 --out easy.png",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "plot", "plot novelty along the route from a results file",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("results", metavar="RESULTS", help="bench folder, results.jsonl/.csv, or run output")
    parser.add_argument("--out", required=True, metavar="PNG", help="image to write")
    parser.add_argument("--task", help="task to plot (bench results; default: the first)")
    parser.add_argument("--seed", type=int, help="seed to plot (bench results; default: the lowest)")
    parser.add_argument("--detector", action="append", help="detectors to plot (default: all)")
    return parser


def _pyplot():
    # deferred: the plots import scikit-learn and matplotlib; `novelty --help` does not
    from ..bench.reports.figures import matplotlib_missing, pyplot

    missing = matplotlib_missing()
    if missing:
        raise UserError("novelty plot needs matplotlib: pip install 'novelty-habituation[plot]'.")
    return pyplot()


def _bench_folder(path: Path) -> Path | None:
    if path.is_dir():
        return path if (path / "results.jsonl").exists() else None
    if path.name == "results.jsonl":
        return path.parent
    if path.suffix.lower() == ".csv":
        with open(path, newline="", encoding="utf-8") as fh:
            header = next(csv.reader(fh), [])
        if "cell_id" in header:
            return path.parent
    return None


#: the columns of a run's output that a plot reads
_COLUMNS = ("novelty", "distance", "y", "x", "alarm", "run")


def _read_run_output(path: Path) -> dict:
    # deferred: `novelty --help` does not read files
    from ..io.tables.table import bounded_lines

    if path.suffix.lower() == ".npz":
        with np.load(path, allow_pickle=False) as npz:
            data = {k: npz[k] for k in npz.files}
    else:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(bounded_lines(fh, str(path))))
        if not rows:
            raise UserError(f"{path} has no rows.")
        try:
            data = {k: np.array([float(r[k]) if r[k] != "" else np.nan for r in rows])
                    for k in rows[0] if k in _COLUMNS}
        except (TypeError, ValueError):
            raise UserError(f"{path}: the {', '.join(_COLUMNS)} columns must be numbers.") from None
    if "x" in data and "y" in data:   # the robot's position: y is its second coordinate, not a label
        data["position_y"] = data.pop("y")
    elif "x" in data:
        print(f"novelty plot: {path} has an 'x' column but no 'y', so no path to draw; the novelty is "
              "drawn along the scans.", file=sys.stderr)
        del data["x"]
    if "novelty" not in data:
        raise UserError(f"{path} has no 'novelty' column; expected the output of 'novelty run' or a bench folder.")
    return data


def _plot_bench(folder: Path, args):
    # deferred: plotting imports matplotlib; `novelty --help` does not
    from ..bench.reports.route import route_figure
    from ..bench.results import ResultsStore

    store = ResultsStore(folder)
    rows = [r for r in store.rows() if r.get("status") == "ok"]
    if not rows:
        raise UserError(f"{folder} holds no successful cells to plot.")
    tasks = list(dict.fromkeys(r["task"] for r in rows))
    task = args.task or tasks[0]
    if task not in tasks:
        raise UserError(f"No task {task!r} in {folder}; it has {', '.join(tasks)}.")
    rows = [r for r in rows if r["task"] == task]
    seed = min(r["seed"] for r in rows) if args.seed is None else args.seed
    rows = [r for r in rows if r["seed"] == seed]
    if args.detector:
        unknown = sorted(set(args.detector) - {r["detector"] for r in rows})
        if unknown:
            raise UserError(f"No detector {unknown[0]!r} for task {task!r}, seed {seed} in {folder}.")
        rows = [r for r in rows if r["detector"] in args.detector]
    if not rows:
        raise UserError(f"No cells for task {task!r} with seed {seed} in {folder}.")
    panels = []
    for row in rows:
        a = store.arrays(row["cell_id"])
        if a is None:
            raise UserError(f"The per-scan novelty of {row['detector']} is missing from {folder}/cells.")
        panels.append((row["detector"], a))
    return route_figure(f"{task}, seed {seed}: novelty of the test scans", panels)


def _plot_path(data: dict, path: Path, plt):
    """The robot's path coloured by novelty, and the novelty scan by scan below it; alarms on both."""
    # deferred: plotting imports matplotlib; `novelty --help` does not
    from ..bench.reports.route import ALARM, plot_route
    from ..io.recording.plotting import plot_path

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 8.4), gridspec_kw={"height_ratios": [3, 1]})
    placed = ~np.isnan(data["x"]) & ~np.isnan(data["position_y"])
    high = max(1.0, float(np.nanmax(data["novelty"])))
    plot_path(top, data["x"][placed], data["position_y"][placed], data["novelty"][placed], vmax=high)
    alarm = data.get("alarm")
    if alarm is not None and np.any(alarm[placed] == 1):
        raised = placed & (alarm == 1)
        top.scatter(data["x"][raised], data["position_y"][raised], s=30, facecolors="none",
                    edgecolors="darkred", linewidths=0.8, zorder=4, label=ALARM)
    top.legend(fontsize=7, loc="best")
    top.set_title(f"{path.name}: novelty on the robot's path", fontsize=10)
    along = plot_route(bottom, data["novelty"], None, None, run=data.get("run"),
                       alarm=None if alarm is None else alarm == 1)
    bottom.set(xlabel=along, ylabel="novelty")
    _legend_if_any(bottom)
    return fig


def _legend_if_any(ax) -> None:
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="upper right", ncols=2)


def run(args) -> int:
    path = Path(args.results)
    if not path.exists():
        raise UserError(f"Results not found: {path}")
    kind = not_regular(path)
    if kind is not None and not path.is_dir():  # a FIFO would block the read, a device never end
        raise UserError(f"{path} is {kind}, not a regular file; expected the output of 'novelty run' or a "
                        "bench folder.")
    check_outputs(_files_read(path), [("--out", args.out)])
    plt = _pyplot()
    try:
        return _plot(path, args, plt)
    except UnicodeDecodeError as exc:
        raise UserError(f"{path} is not UTF-8 text ({exc.reason}); expected the CSV output of 'novelty run' "
                        "or a bench folder.") from None


def _files_read(path: Path) -> list[tuple[str, Path]]:
    """What a plot of ``path`` reads: the file, or a bench folder's rows and per-cell arrays."""
    folder = path if path.is_dir() else path.parent if path.name in ("results.jsonl", "results.csv") else None
    files = [] if path.is_dir() else [("RESULTS", path)]
    if folder is not None:
        files += [("RESULTS", folder / "results.jsonl"), ("RESULTS", folder / "cells")]
    return files


def _plot(path: Path, args, plt) -> int:
    folder = _bench_folder(path)
    if folder is not None:
        fig = _plot_bench(folder, args)
    elif path.is_dir():
        raise UserError(f"{path} is not a benchmark output folder (no results.jsonl).")
    else:
        from ..bench.reports.route import plot_route

        data = _read_run_output(path)
        if "x" in data:
            fig = _plot_path(data, path, plt)
        else:
            fig, ax = plt.subplots(figsize=(9, 3.2))
            alarm = data.get("alarm")
            along = plot_route(ax, data["novelty"], data.get("y"), data.get("distance"), run=data.get("run"),
                               alarm=None if alarm is None else alarm == 1)
            ax.set(xlabel=along, ylabel="novelty", title=path.name)
            _legend_if_any(ax)
    if fig.get_layout_engine() is None:  # the bench figure is laid out as it is drawn
        fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print(f"Wrote {args.out}.", file=sys.stderr)
    return 0
