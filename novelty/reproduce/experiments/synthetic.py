"""Synthetic corridors: the paper's map on perceptions that repeat exactly, or almost.

Each corridor is a run of 100 scans of 16 values in [0, 1] made of ``K``
perceptions drawn once per seed (uniform in [0, 1]^16), each held for 100 / K
consecutive scans, as a wall then a door then a wall again would be. A noisy
corridor holds one perception with Gaussian noise of ``level`` times each
value (fresh noise in every scan and every run; clipped to [0, 1]). The HSOM
(``hsom``, the paper's constants) runs A's six trials on it (L, NL, L, NL, L,
NL from an untrained map).

What it shows: with a shared learning rate the winner and its 8 neighbours
all move the same fraction of the way to the input, so their distances to a
repeated perception shrink by the same factor and the winner stays the
winner: exact repetition settles. Noise of a fraction of a percent decides
between units that have become near-copies of each other, and the winning
unit wanders over units that were habituated only as neighbours.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._common import PAPER_A, Result, mean_trials, parallel, plot_trials, six_trials, span, trial_columns

NAME = "synthetic"
TITLE = "Synthetic corridors: exact repetition settles, 0.05% noise does not"

#: (label, number of perceptions K, relative noise level)
CORRIDORS = (("K=1, exact", 1, 0.0), ("K=2, exact", 2, 0.0), ("K=5, exact", 5, 0.0),
             ("K=10, exact", 10, 0.0), ("K=1, noise 0.05%", 1, 0.0005), ("K=1, noise 1%", 1, 0.01))
SCANS, FEATURES = 100, 16
#: Integrated novelty of the paper's settled run (A, trial 6).
SETTLED = 0.3
SETTLED_COLUMN = f"settled (<{SETTLED}) seeds"


def corridor_runs(k: int, level: float, seed: int, n_runs: int = 6) -> list[np.ndarray]:
    """``n_runs`` runs of a corridor of ``k`` perceptions with relative noise ``level``."""
    # the same perceptions at every noise level; the noise from a stream of its own
    perceptions = np.random.default_rng([seed, k]).uniform(0.0, 1.0, size=(k, FEATURES))
    rng = np.random.default_rng([seed, k, int(round(level * 1e6))])
    base = perceptions[np.arange(SCANS) * k // SCANS]
    runs = []
    for _ in range(n_runs):
        noise = level * base * rng.standard_normal(base.shape)
        runs.append(np.clip(base + noise, 0.0, 1.0))
    return runs


def _one(job):
    label, k, level, seed = job
    found = six_trials(seed, runs=corridor_runs(k, level, seed))
    return label, seed, found


def run(out: Path, seeds=range(10), jobs: int = 1) -> Result:
    jobs_list = [(label, k, level, s) for label, k, level in CORRIDORS for s in seeds]
    by_label: dict[str, list[dict]] = {}
    for label, _seed, found in parallel(_one, jobs_list, jobs):
        by_label.setdefault(label, []).append(found)
    rows = []
    for label, _k, _level in CORRIDORS:
        found = by_label[label]
        integrated = np.array([f["integrated"] for f in found])
        row = {"corridor": label, **trial_columns(mean_trials(found))}
        row["trial 6 max"] = float(integrated[:, 5].max())
        row[SETTLED_COLUMN] = f"{int(np.sum(integrated[:, 5] < SETTLED))}/{len(found)}"
        row["winning units (L runs)"] = float(np.mean([f["learning_winners"] for f in found]))
        rows.append(row)
    figure = plot_trials(rows, "corridor", out / f"{NAME}.png",
                         "HSOM on synthetic corridors (mean over seeds)")
    nseeds = len(list(seeds))
    exact2, noisy = rows[1], rows[4]
    findings = [
        f"Two perceptions repeated exactly: {exact2['trial 1']:.2f} -> {exact2['trial 6']:.2f} "
        f"(mean of {nseeds} seeds), {exact2['winning units (L runs)']:.1f} winning units.",
        f"One perception with 0.05% noise: {noisy['trial 1']:.2f} -> {noisy['trial 6']:.2f}, "
        f"{noisy['winning units (L runs)']:.1f} winning units over the three learning runs.",
    ]
    note = (f"Mean integrated novelty over seeds {span(seeds)}; the paper's A: "
            + ", ".join(f"{v:.2f}" for v in PAPER_A) + ".")
    return Result(NAME, TITLE, rows, findings, figure, note)
