"""The simulated corridor A with one switch of the simulator changed at a time.

Each row runs A's six trials (L, NL, L, NL, L, NL; the paper's HSOM) on the
same seeds with one departure of the simulator from a perfect, paper-only
world removed: no run-to-run variation of the drive, no sensor noise (nor
dropouts), no multipath echoes, no edge echoes, only the two features the
paper names (the crack and the right-hand door at about 3 m, without the
office doors the map adds), or readings rounded to whole inches as the
Nomad 200 reports them. The last two rows turn several switches off at once.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from novelty.sonar import PolaroidRanger, RunVariation, corridor_a
from novelty.sonar.ranger import INCH

from ._common import PAPER_A, Result, mean_trials, parallel, plot_trials, six_trials, span, trial_columns

NAME = "ablations"
TITLE = "Simulator ablations: corridor A with one switch changed at a time"

_QUIET = dict(noise_sd=0.0, noise_fraction=0.0, dropout=0.0)
_PHYSICS_OFF = (("ranger", PolaroidRanger(**_QUIET, multipath=False, edges=False)),
                ("variation", RunVariation().none()))

#: label -> (environment, simulator options)
SWITCHES = {
    "as simulated": ("a", ()),
    "no run-to-run variation": ("a", (("variation", RunVariation().none()),)),
    "no sensor noise or dropouts": ("a", (("ranger", PolaroidRanger(**_QUIET)),)),
    "no multipath": ("a", (("ranger", PolaroidRanger(multipath=False)),)),
    "no edge echoes": ("a", (("ranger", PolaroidRanger(edges=False)),)),
    "only the paper's features": ("a-named", ()),
    "whole inches": ("a", (("ranger", PolaroidRanger(resolution=INCH)),)),
    "all four physical switches off": ("a", _PHYSICS_OFF),
    "all four off, only the paper's features": ("a-named", _PHYSICS_OFF),
}

_ENVIRONMENTS = {}


def environment(key: str):
    """``"a"`` or the corridor A with only the paper's features (built once per process)."""
    if key == "a":
        return "a"
    if key not in _ENVIRONMENTS:
        _ENVIRONMENTS[key] = corridor_a(extra_doors=False)
    return _ENVIRONMENTS[key]


def _one(job):
    label, seed = job
    env, options = SWITCHES[label]
    return label, six_trials(seed, environment=environment(env), options=options)


def summarise(by_label: dict[str, list[dict]]) -> list[dict]:
    """One row per switch: mean integrated novelty per trial and what the map did."""
    rows = []
    base6 = mean_trials(by_label["as simulated"])[5]
    for label, found in by_label.items():
        integrated = mean_trials(found)
        row = {"simulator": label, **trial_columns(integrated)}
        row["trial 6 / as simulated"] = float(integrated[5] / base6)
        row["winning units (L runs)"] = float(np.mean([f["learning_winners"] for f in found]))
        row["trial 6 from units won <= 2 times"] = f"{np.nanmean([f['rare_share'] for f in found]):.0%}"
        rows.append(row)
    return rows


def run(out: Path, seeds=range(10), jobs: int = 1) -> Result:
    found = parallel(_one, [(label, s) for label in SWITCHES for s in seeds], jobs)
    by_label: dict[str, list[dict]] = {label: [] for label in SWITCHES}
    for label, f in found:
        by_label[label].append(f)
    rows = summarise(by_label)
    base = rows[0]
    paper_gap = base["trial 6"] / PAPER_A[5]
    findings = [f"As simulated, trial 6 is {base['trial 6']:.2f}: {paper_gap:.0f} times the paper's "
                f"{PAPER_A[5]:.2f}."]
    for row in rows[1:]:
        findings.append(f"{row['simulator']}: trial 1 {row['trial 1']:.2f}, trial 6 {row['trial 6']:.2f} "
                        f"({row['trial 6 / as simulated']:.2f} of as simulated; "
                        f"{row['trial 6'] / PAPER_A[5]:.0f}x the paper's).")
    note = (f"Mean integrated novelty over seeds {span(seeds)} (paper's HSOM, A's six trials); the "
            "paper's A: " + ", ".join(f"{v:.2f}" for v in PAPER_A) + ".")
    figure = plot_trials(rows, "simulator", out / f"{NAME}.png",
                         "Corridor A, one simulator switch at a time (mean over seeds)", "as simulated")
    return Result(NAME, TITLE, rows, findings, figure, note)
