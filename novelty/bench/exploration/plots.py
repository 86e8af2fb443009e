"""Plots of an exploration run (matplotlib, optional).

- ``exploration-route-<task>.png``: novelty along the whole exploration, one
  panel a detector, runs separated and named, scans of a tracked feature
  marked (first exposure red, later exposures orange), the warm-up shaded;
  the lowest seed.
- ``exploration-exposure-<task>.png``: novelty against exposure count, one
  panel a detector, one line a recurring feature, the familiar level of the
  same runs dashed; mean over seeds.
- ``exploration-learning-<task>.png``: integrated novelty per run (the
  paper's Table 1 measure) as a learning curve, one line a detector; mean
  over seeds.

Each figure's title says which seed(s) it shows.

Shares its name with ``novelty/bench/holdout/plots.py``: each benchmark protocol's package holds its
own metrics, plots and summary.
"""

from __future__ import annotations

import json
from collections import defaultdict
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from ..reports.figures import grid, pyplot, save, slug
from ..reports.route import route_legend, shade_alarms

__all__ = ["plot_exploration", "plot_exploration_route", "exploration_route_figure", "plot_exposure_curves",
           "plot_learning_curves", "mean_over_seeds"]


def _cells(rows: Sequence[dict]) -> dict[str, dict[str, list[dict]]]:
    """``{task: {detector: [rows, by seed]}}`` of the successful exploration cells."""
    out: dict[str, dict[str, list[dict]]] = defaultdict(lambda: defaultdict(list))
    for row in sorted(rows, key=lambda r: (r["seed"], r["cell_id"])):
        if row.get("status") == "ok" and row.get("policy"):
            out[row["task"]][row["detector"]].append(row)
    return out


def _seeds(cells: dict[str, list[dict]]) -> str:
    seeds = sorted({r["seed"] for rows in cells.values() for r in rows})
    return f"seed {seeds[0]}" if len(seeds) == 1 else f"mean over seeds {', '.join(map(str, seeds))}"


def plot_exploration_route(task: str, cells: dict, arrays: Callable, out: Path) -> Path | None:
    """Novelty along the whole exploration, one panel a detector (lowest seed), saved in ``out``."""
    fig = exploration_route_figure(task, cells, arrays)
    return save(fig, out / f"exploration-route-{slug(task)}.png", tight=False)


def exploration_route_figure(task: str, cells: dict, arrays: Callable):
    """The figure of :func:`plot_exploration_route`: each scan after the warm-up above the threshold an alarm."""
    plt = pyplot()
    first = {d: rows[0] for d, rows in cells.items()}
    seed = min(r["seed"] for r in first.values())
    fig, axes = plt.subplots(len(first), 1, figsize=(11, 1.6 * len(first) + 1.2), squeeze=False, sharex=True,
                             layout="constrained")
    for ax, (detector, row) in zip(axes[:, 0], first.items()):
        a = arrays(row["cell_id"])
        if a is None:
            continue
        x = np.arange(a["novelty"].size)
        ax.plot(x, a["novelty"], linewidth=0.7, color="tab:blue", label="novelty")
        tracked = a["exposure"] >= 0
        for mask, colour, label in ((tracked & (a["exposure"] == 0), "tab:red", "first exposure"),
                                    (a["exposure"] > 0, "tab:orange", "later exposures")):
            ax.scatter(x[mask], a["novelty"][mask], s=4, color=colour, label=label, zorder=3)
        starts = np.r_[0, np.flatnonzero(np.diff(a["run"])) + 1]
        for i, s in enumerate(starts):
            ax.axvline(s, color="0.8", linewidth=0.6, label="run start (its environment named above)" if i == 1 else None)
            if ax is axes[0, 0]:
                ax.text(s + 2, 1.02, str(a["environment"][s]), fontsize=6, transform=ax.get_xaxis_transform())
        ax.axvspan(0, starts[int(a["warmup"])] if int(a["warmup"]) < starts.size else x[-1],
                   color="0.9", zorder=0, label="warm-up runs")
        threshold = float(a["threshold"])
        if np.isfinite(threshold):
            ax.axhline(threshold, color="k", linestyle="--", linewidth=0.6,
                       label="alarm threshold (from the last warm-up run)")
            after = x >= (starts[int(a["warmup"])] if int(a["warmup"]) < starts.size else x[-1] + 1)
            shade_alarms(ax, x, after & (a["novelty"] > threshold))
            ax.set_ylim(top=max(1.0, float(np.max(a["novelty"]))) * 1.12)
        ax.set_title(f"{detector} (seed {row['seed']})", fontsize=8, loc="left")
        ax.set_ylabel("novelty", fontsize=7)
    axes[-1, 0].set_xlabel("scan (the runs in order)")
    fig.suptitle(f"{task}: novelty of every scan before it is learned, seed {seed}", fontsize=10)
    route_legend(fig, axes[:, 0])
    return fig


def mean_over_seeds(curves: Sequence[np.ndarray]) -> np.ndarray:
    """The mean of each position over the seeds' curves, of the finite values there.

    NaN where no seed has a value (an exposure no run reached, runs without
    familiar scans): a gap in the plotted line, not numpy's "Mean of empty
    slice" warning.
    """
    stack = np.asarray(curves, dtype=np.float64)
    finite = np.isfinite(stack)
    count = finite.sum(axis=0)
    total = np.where(finite, stack, 0.0).sum(axis=0)
    return np.divide(total, count, out=np.full(count.shape, np.nan), where=count > 0)


def plot_exposure_curves(task: str, cells: dict, arrays: Callable, out: Path) -> Path | None:
    """Novelty against exposure count, one panel a detector; familiar level dashed; mean over seeds."""
    plt = pyplot()
    n_rows, n_cols = grid(len(cells))
    fig, axes = plt.subplots(n_rows, n_cols, figsize=(4 * n_cols, 3.1 * n_rows), squeeze=False)
    for ax, (detector, rows) in zip(axes.flat, cells.items()):
        novelty, familiar = defaultdict(list), defaultdict(list)
        for row in rows:
            a = arrays(row["cell_id"])
            if a is None:
                continue
            for i, f in enumerate(a["curve_features"].tolist()):
                novelty[f].append(a["curve_novelty"][i])
                familiar[f].append(a["curve_familiar"][i])
        for f in sorted(novelty):
            width = min(len(v) for v in novelty[f])
            nov = mean_over_seeds([v[:width] for v in novelty[f]])
            fam = mean_over_seeds([v[:width] for v in familiar[f]])
            if np.sum(np.isfinite(nov)) < 2:
                continue  # met once: no curve
            ks = np.arange(1, width + 1)
            line, = ax.plot(ks, nov, marker="o", markersize=3, linewidth=1, label=f)
            ax.plot(ks, fam, linestyle="--", linewidth=0.8, color=line.get_color())
        ax.plot([], [], linestyle="--", linewidth=0.8, color="0.3", label="familiar scans, same runs")
        ax.set_title(detector, fontsize=8, loc="left")
        ax.set_xlabel("exposure (1 = first encounter)", fontsize=7)
        ax.set_ylabel("mean novelty", fontsize=7)
        ax.legend(fontsize=5)
    for ax in list(axes.flat)[len(cells):]:
        ax.set_visible(False)
    fig.suptitle(f"{task}: novelty of each recurring feature at each exposure (dashed: familiar scans "
                 f"of the same runs), {_seeds(cells)}", fontsize=9)
    return save(fig, out / f"exploration-exposure-{slug(task)}.png")


def plot_learning_curves(task: str, cells: dict, out: Path) -> Path | None:
    """Integrated novelty per run, one line a detector (mean over seeds)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.2))
    warmup = 0
    for detector, rows in cells.items():
        curves = [json.loads(r["integrated_per_run"]) for r in rows if r.get("integrated_per_run")]
        if not curves:
            continue
        width = min(len(c) for c in curves)
        ax.plot(np.arange(width), np.mean([c[:width] for c in curves], axis=0), marker=".", label=detector)
        warmup = int(rows[0].get("warmup_runs") or 0)
    if warmup:
        ax.axvspan(-0.5, warmup - 0.5, color="0.9", zorder=0, label="warm-up runs")
    ax.set(xlabel="run", ylabel="integrated novelty (resting subtracted)")
    ax.set_title(f"{task}: integrated novelty per run, {_seeds(cells)}", fontsize=9)
    ax.legend(fontsize=6, ncols=2)
    return save(fig, out / f"exploration-learning-{slug(task)}.png")


def plot_exploration(rows: Sequence[dict], arrays: Callable[[str], dict | None], out) -> list[Path]:
    """Every exploration plot of a run into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for task, cells in _cells(rows).items():
        paths += [plot_exploration_route(task, cells, arrays, out),
                  plot_exposure_curves(task, cells, arrays, out),
                  plot_learning_curves(task, cells, out)]
    return [p for p in paths if p is not None]
