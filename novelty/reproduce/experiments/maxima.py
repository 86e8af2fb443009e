"""Which of Table 1's maxima each integration of Stanley's synapse can reach.

The maximum of a run is the efficacy of the synapse of some winning unit.
Under the paper's rule (others hold) an efficacy only ever falls from
y0 = 1: by winner steps (tau = 3.33) and neighbour steps (tau = 14.3) with
S = 1, each a map ``y -> y_inf + a (y - y_inf)`` with the same fixed point
``y_inf = y0 - 1/alpha``, so the order of the steps does not matter and
after ``w`` winner and ``n`` neighbour steps::

    y = y_inf + (y0 - y_inf) * a_w**w * a_n**n

with ``a = 1 - alpha/tau`` for a unit Euler step and ``a = exp(-alpha/tau)``
for the exact solution. The values are computed here by stepping
:class:`~novelty.habituation.stanley.StanleySynapse` itself. A value of
Table 1 "fits" a pair (w, n) when the efficacy rounds to it at two decimals.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from novelty.habituation.stanley import StanleySynapse
from novelty.reproduce import PAPER_TABLE1

from ._common import Result, pyplot

NAME = "maxima"
TITLE = "Table 1's maxima: which values unit Euler steps and the exact solution can reach"

MAX_WINNER_STEPS, MAX_NEIGHBOUR_STEPS = 12, 60
METHODS = ("euler", "exact")


def efficacies(method: str, winner_steps: int = MAX_WINNER_STEPS,
               neighbour_steps: int = MAX_NEIGHBOUR_STEPS) -> np.ndarray:
    """``E[w, n]``: a synapse's efficacy after ``w`` winner steps, then ``n`` neighbour steps."""
    out = np.empty((winner_steps + 1, neighbour_steps + 1))
    for w in range(winner_steps + 1):
        bank = StanleySynapse(method=method).initialize(2)  # unit 0 is watched; unit 1 wins
        for _ in range(w):
            bank.step(0, [])
        for n in range(neighbour_steps + 1):
            out[w, n] = bank.efficacy_[0]
            bank.step(1, [0])
        # the step after the last neighbour step is never read
    return out


def fits(value: float, table: np.ndarray) -> list[tuple[int, int]]:
    """The (w, n) whose efficacy rounds to ``value`` at two decimals, fewest steps first."""
    w, n = np.nonzero(np.round(table, 2) == round(value, 2))
    return sorted(zip(w.tolist(), n.tolist()), key=lambda p: (p[0] + p[1], p[1]))


def _describe(table: np.ndarray, pairs: list[tuple[int, int]], winner_only: bool) -> str:
    if winner_only:
        pairs = [p for p in pairs if p[1] == 0]
    if not pairs:
        return "none"
    w, n = pairs[0]
    steps = f"{w} winner" + (f" + {n} neighbour" if n else "")
    return f"{steps} ({table[w, n]:.4f})"


def _rows_of(value: float) -> str:
    hits = [f"{e} {t}" for e, t, _, _, m in PAPER_TABLE1 if round(m, 2) == round(value, 2)]
    return ", ".join(hits)


def run(out: Path, seeds=None, jobs: int = 1) -> Result:
    """``seeds`` and ``jobs`` are accepted for a common signature; nothing here is random."""
    tables = {m: efficacies(m) for m in METHODS}
    values = sorted({m for *_, m in PAPER_TABLE1}, reverse=True)
    rows = []
    for v in values:
        row = {"Table 1 maximum": v, "rows of Table 1": _rows_of(v)}
        for m in METHODS:
            pairs = fits(v, tables[m])
            row[f"{m}: winner steps only"] = _describe(tables[m], pairs, True)
            row[f"{m}: fewest steps"] = _describe(tables[m], pairs, False)
        rows.append(row)
    euler_w = ", ".join(f"{y:.4f}" for y in tables["euler"][1:5, 0])
    exact_w = ", ".join(f"{y:.4f}" for y in tables["exact"][1:5, 0])
    findings = [f"Winner steps alone from 1: Euler {euler_w}, ...; exact {exact_w}, ....",
                "Winner and neighbour steps commute (one fixed point), so only their numbers matter."]
    note = (f"Steps searched: up to {MAX_WINNER_STEPS} winner and {MAX_NEIGHBOUR_STEPS} neighbour "
            "steps; tau = 3.33 (winner), 14.3 (neighbours), alpha = 1.05, y0 = 1, others hold.")
    return Result(NAME, TITLE, rows, findings, _plot(tables, values, out / f"{NAME}.png"), note)


def _plot(tables: dict, values: list[float], path: Path) -> Path:
    plt = pyplot()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(7.6, 3.6), sharey=True)
    for ax, method in zip(axes, METHODS):
        table = tables[method]
        for w in range(5):
            n = np.arange(9)
            ax.plot(w + n, table[w, :9], marker="o", ms=3, lw=0.8, label=f"{w} winner step(s) then neighbour")
        for v in values:
            ax.axhline(v, color="0.6", lw=0.6, ls=":")
        ax.set_title(f"{method} integration", fontsize=9)
        ax.set_xlabel("winner + neighbour steps")
    axes[0].set_ylabel("efficacy (dotted: Table 1's maxima)")
    axes[0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
