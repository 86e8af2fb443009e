"""Plots of a hold-out run (matplotlib, optional): ROC curves, novelty along the route
(:mod:`novelty.bench.reports.route`), ROC AUC per task and boxplots over seeds.

Every function returns the paths it wrote, and every figure says which seeds
it shows (ROC curves and routes: the lowest seed of each task) or aggregates.
The critical-difference diagram, shared by the protocols, is
:mod:`novelty.bench.reports.critical_difference`.

Shares its name with ``novelty/bench/exploration/plots.py``: each benchmark protocol's package holds
its own metrics, plots and summary.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from ..reports.figures import grid, pyplot, save, seeds_text, slug, wrapped
from ..reports.ranking import detector_order, per_task
from ..reports.route import route_figure
from ..stats.aggregate import as_float
from . import metrics

__all__ = ["plot_run", "plot_roc", "plot_routes", "plot_ranking", "plot_boxplots"]


def _first_seed_cells(rows: Sequence[dict]) -> dict[str, dict[str, dict]]:
    """``{task: {detector: row}}`` for the lowest seed of each successful (task, detector)."""
    chosen: dict[str, dict[str, dict]] = defaultdict(dict)
    for row in sorted(rows, key=lambda r: r["seed"]):
        if row.get("status") == "ok" and row["detector"] not in chosen[row["task"]]:
            chosen[row["task"]][row["detector"]] = row
    return chosen


def _seeds(rows: Sequence[dict]) -> str:
    return seeds_text([r["seed"] for r in rows if r.get("status") == "ok"])


def plot_roc(rows: Sequence[dict], arrays: Callable[[str], dict | None], out: Path) -> list[Path]:
    """One panel a task, one ROC curve a detector (lowest seed)."""
    plt = pyplot()
    chosen = _first_seed_cells(rows)
    if not chosen:
        return []
    n_rows, n_cols = grid(len(chosen))
    fig, axes = plt.subplots(n_rows, n_cols, figsize=(4.2 * n_cols, 4 * n_rows), squeeze=False)
    for ax, (task, cells) in zip(axes.flat, chosen.items()):
        seed = min(row["seed"] for row in cells.values())
        for detector, row in cells.items():
            a = arrays(row["cell_id"])
            if a is None or not 0 < a["y"].sum() < a["y"].size:
                continue
            fpr, tpr, _ = metrics.roc_points(a["novelty"], a["y"])
            ax.plot(fpr, tpr, drawstyle="steps-post", label=f"{detector} ({row['roc_auc']:.2f})")
        ax.plot([0, 1], [0, 1], color="0.7", linewidth=0.8, linestyle=":")
        ax.set(title=f"{task} (seed {seed})", xlabel="false-positive rate", ylabel="true-positive rate",
               xlim=(0, 1), ylim=(0, 1.01))
        ax.legend(fontsize=7, loc="lower right")
    for ax in list(axes.flat)[len(chosen):]:
        ax.set_visible(False)
    fig.suptitle(wrapped("ROC curves of one seed of each task, named in each panel (that seed's ROC AUC in "
                         "brackets; dotted: chance)", fig), fontsize=10)
    path = save(fig, out / "roc.png")
    return [path]


def plot_routes(rows: Sequence[dict], arrays: Callable[[str], dict | None], out: Path) -> list[Path]:
    """One figure a task: the test novelty along the route, one panel a detector (lowest seed)."""
    paths = []
    for task, cells in _first_seed_cells(rows).items():
        panels = [(detector, a) for detector, row in cells.items() if (a := arrays(row["cell_id"])) is not None]
        if not panels:
            continue
        seed = min(row["seed"] for row in cells.values())
        fig = route_figure(f"{task}, seed {seed}: novelty of the test scans", panels)
        paths.append(save(fig, out / f"route-{slug(task)}.png", tight=False))
    return paths


def plot_ranking(rows: Sequence[dict], out: Path) -> list[Path]:
    """Mean ROC AUC per task and detector, with the spread over seeds."""
    plt = pyplot()
    order = detector_order(rows)
    table = per_task(rows)
    tasks = list(dict.fromkeys(r["task"] for r in rows))
    if not order or not tasks:
        return []
    fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(order) + 3), 4.5))
    width = 0.8 / len(tasks)
    for j, task in enumerate(tasks):
        means = [table.get(d, {}).get(task, (np.nan, np.nan))[0] for d in order]
        sds = [table.get(d, {}).get(task, (np.nan, np.nan))[1] for d in order]
        xs = np.arange(len(order)) + (j - (len(tasks) - 1) / 2) * width
        ax.bar(xs, means, width, yerr=np.nan_to_num(sds), capsize=2, label=task)
    ax.errorbar([], [], yerr=[], color="k", capsize=2, linestyle="none", label="± sd over seeds")
    ax.axhline(0.5, color="0.6", linestyle=":", linewidth=0.8, label="chance (0.5)")
    ax.set_xticks(np.arange(len(order)), order, rotation=30, ha="right", fontsize=8)
    ax.set(ylabel="mean ROC AUC over seeds", ylim=(0, 1.05),
           title=f"Detectors ranked by mean ROC AUC ({_seeds(rows)}; a bar a task)")
    ax.legend(fontsize=7, ncols=min(len(tasks), 4))
    path = save(fig, out / "ranking.png")
    return [path]


def plot_boxplots(rows: Sequence[dict], out: Path) -> list[Path]:
    """One panel a task: the ROC AUC of each detector over the seeds, a box and the seeds' points."""
    plt = pyplot()
    order = detector_order(rows)
    tasks = list(dict.fromkeys(r["task"] for r in rows if r.get("status") == "ok"))
    if not tasks:
        return []
    fig, axes = plt.subplots(len(tasks), 1, figsize=(max(6, 0.7 * len(order) + 2), 3.2 * len(tasks)),
                             squeeze=False)
    for ax, task in zip(axes[:, 0], tasks):
        values = [np.array([as_float(r.get("roc_auc")) for r in rows if r["task"] == task
                            and r["detector"] == d and r.get("status") == "ok"]) for d in order]
        values = [v[~np.isnan(v)] for v in values]
        positions = np.arange(1, len(order) + 1)
        ax.boxplot(values, positions=positions, widths=0.6, showfliers=False, whis=(0, 100),
                   medianprops={"color": "tab:orange"})
        for x, v in zip(positions, values):
            ax.plot(np.full(v.size, x), v, "o", color="tab:blue", markersize=3, alpha=0.7)
        ax.plot([], [], "o", color="tab:blue", markersize=3, label="a seed")
        ax.plot([], [], color="tab:orange", label="median over seeds")
        ax.plot([], [], "s", markerfacecolor="none", markeredgecolor="k",
                label="box: middle half of the seeds; whiskers: all")
        ax.axhline(0.5, color="0.6", linestyle=":", linewidth=0.8, label="chance (0.5)")
        ax.legend(fontsize=7, loc="lower right")
        ax.set_xticks(positions, order, rotation=30, ha="right", fontsize=8)
        ax.set(ylabel="ROC AUC", ylim=(0, 1.02),
               title=f"{task}: ROC AUC over {_seeds([r for r in rows if r['task'] == task])}")
    path = save(fig, out / "boxplot-roc-auc.png")
    return [path]


def plot_run(rows: Sequence[dict], arrays: Callable[[str], dict | None], out) -> list[Path]:
    """Every plot of a run into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return (plot_roc(rows, arrays, out) + plot_routes(rows, arrays, out) + plot_ranking(rows, out)
            + plot_boxplots(rows, out))
