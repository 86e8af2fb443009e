"""Options of the map that are not in the paper, on the simulated corridor A.

The paper gives the winner and its 8 neighbours one learning rate, 0.25,
and integrates Stanley's equation (implicitly) in unit steps. Two options
of ours are varied here, each labelled as not the paper's:

- ``neighbour_learning_rate`` of :class:`~novelty.clusterers.som.SOM`: the
  neighbours move towards the input at a rate of their own, so the winner
  stays nearer its perception than its neighbours are and is not replaced
  by a near-copy of itself;
- ``method`` of :class:`~novelty.habituation.stanley.StanleySynapse`:
  explicit Euler steps (the default, the paper's values imply it) or the
  exact solution.

The last rows run the same options on corridor A with the simulator's
physical switches off and only the paper's features (see ``ablations``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from . import ablations
from ._common import PAPER_A, Result, mean_trials, parallel, plot_trials, six_trials, span, trial_columns

NAME = "sensitivity"
TITLE = "Sensitivity of the map (options not in the paper): neighbour learning rate, integration"

KEY = "map (not the paper's unless said)"
PAPER_MAP = "paper (shared rate 0.25, Euler)"

#: label -> (map parameters, simulator switch of ``ablations``)
SETTINGS = {
    PAPER_MAP: ({}, "as simulated"),
    "exact integration": ({"method": "exact"}, "as simulated"),
    "neighbour rate 0.1": ({"neighbour_learning_rate": 0.1}, "as simulated"),
    "neighbour rate 0.05": ({"neighbour_learning_rate": 0.05}, "as simulated"),
    "neighbour rate 0.05, exact": ({"neighbour_learning_rate": 0.05, "method": "exact"}, "as simulated"),
    "neighbour rate 0.02": ({"neighbour_learning_rate": 0.02}, "as simulated"),
    "neighbour rate 0": ({"neighbour_learning_rate": 0.0}, "as simulated"),
    "paper, stripped simulator": ({}, "all four off, only the paper's features"),
    "neighbour rate 0.05, stripped simulator": ({"neighbour_learning_rate": 0.05},
                                                "all four off, only the paper's features"),
}


def _one(job):
    """Every setting on one corridor and seed (the runs are simulated once and cached)."""
    switch, seed = job
    env, options = ablations.SWITCHES[switch]
    return [(label, six_trials(seed, params, environment=ablations.environment(env), options=options))
            for label, (params, on) in SETTINGS.items() if on == switch]


def fold(integrated) -> float:
    """The largest factor between a trial and the paper's same trial, either way."""
    ratio = np.asarray(integrated) / np.asarray(PAPER_A)
    return float(np.max(np.maximum(ratio, 1.0 / ratio)))


def run(out: Path, seeds=range(10), jobs: int = 1) -> Result:
    switches = sorted({switch for _, switch in SETTINGS.values()})
    found = parallel(_one, [(switch, s) for switch in switches for s in seeds], jobs)
    by_label: dict[str, list[dict]] = {label: [] for label in SETTINGS}
    for label, f in (pair for group in found for pair in group):
        by_label[label].append(f)
    rows = []
    for label, results in by_label.items():
        integrated = mean_trials(results)
        row = {KEY: label, **trial_columns(integrated)}
        row["largest factor from the paper"] = fold(integrated)
        row["winning units (L runs)"] = float(np.mean([f["learning_winners"] for f in results]))
        rows.append(row)
    findings = [f"{r[KEY]}: " + " / ".join(f"{r[f'trial {t}']:.2f}" for t in range(1, 7))
                + f", within {r['largest factor from the paper']:.1f}x of every trial of the paper's"
                for r in rows]
    note = (f"Mean integrated novelty over seeds {span(seeds)}; the paper's A: "
            + ", ".join(f"{v:.2f}" for v in PAPER_A) + ".")
    figure = plot_trials(rows, KEY, out / f"{NAME}.png",
                         "Corridor A: options of the map not in the paper (mean over seeds)", PAPER_MAP)
    return Result(NAME, TITLE, rows, findings, figure, note)
