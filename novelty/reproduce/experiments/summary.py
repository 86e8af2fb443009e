"""One table from all the experiments: each discrepancy of Table 1, what explains it, the numbers.

Shares its name with ``novelty/bench/exploration/summary.py``, ``novelty/bench/holdout/summary.py``,
``novelty/bench/reports/summary.py``: each benchmark protocol's package holds its own metrics, plots
and summary; the reports and the paper's experiments summarise a run of theirs.
"""

from __future__ import annotations

import numpy as np

from ._common import PAPER_A, Result
from .synthetic import SETTLED_COLUMN
from .table1 import OWN_HOLDS

_SINGLE_SWITCHES = ("no run-to-run variation", "no sensor noise or dropouts", "no multipath", "no edge echoes",
                    "whole inches")

NAME = "summary"


def _row(result: Result, key: str, label: str) -> dict:
    return next(r for r in result.rows if r[key] == label)


def _table1_ratio(table1: Result, column: str, experiments=("A*", "B", "C")) -> str:
    """Median and range of ours / the paper's over the trials of ``experiments`` (controls left out)."""
    ratios = [r[column] / r["paper integrated"] for r in table1.rows
              if r["Exp"] in experiments and r["Trial"] != "Control"]
    return f"median {np.median(ratios):.1f}x ({min(ratios):.1f}-{max(ratios):.0f}x)"


def rows(results: dict[str, Result]) -> list[dict]:
    """The summary; ``results`` holds the results of every experiment by name."""
    t1, syn, abl, sen, mx = (results[k] for k in
                             ("table1", "synthetic", "ablations", "sensitivity", "maxima"))
    base = _row(abl, "simulator", "as simulated")
    exact2, noisy = _row(syn, "corridor", "K=2, exact"), _row(syn, "corridor", "K=1, noise 0.05%")
    own = _row(sen, "map (not the paper's unless said)", "neighbour rate 0.05")
    named = _row(abl, "simulator", "only the paper's features")
    off = _row(abl, "simulator", "all four physical switches off")
    stripped = _row(abl, "simulator", "all four off, only the paper's features")
    singles = [r["trial 6 / as simulated"] for r in abl.rows if r["simulator"] in _SINGLE_SWITCHES]
    ratio, own_ratio = _table1_ratio(t1, "mean"), _table1_ratio(t1, "neighbour rate 0.05: mean")
    claims = {r["claim (the paper)"]: r for r in t1.tables["claims"]}
    c_control = claims["C's control: far more novelty"]
    nothing_else = claims["no other novel features were detected"]
    m042 = _row(mx, "Table 1 maximum", 0.42)
    m035 = _row(mx, "Table 1 maximum", 0.35)
    return [
        {"discrepancy": f"A does not settle: trial 6 {base['trial 6']:.2f} against {PAPER_A[5]:.2f}",
         "explanation": "winner drift: one learning rate for the winner and its 8 neighbours makes them "
                        "near-copies; tiny differences then pick the winner, often a unit habituated only "
                        "as a neighbour",
         "experiment": "synthetic, sensitivity, ablations",
         "numbers": f"2 exact perceptions: trial 6 {exact2['trial 6']:.2f} ({exact2[SETTLED_COLUMN]} "
                    f"seeds settle); 1 perception, 0.05% noise: {noisy['trial 6']:.2f} "
                    f"({noisy[SETTLED_COLUMN]}), {noisy['winning units (L runs)']:.0f} winning units; "
                    f"simulated A: {base['trial 6 from units won <= 2 times']} of trial 6 from units that won "
                    f"<= 2 times; neighbour rate 0.05: trial 6 {own['trial 6']:.2f}, every A trial within "
                    f"{own['largest factor from the paper']:.1f}x of the paper's"},
        {"discrepancy": f"A's first run: {base['trial 1']:.2f} against {PAPER_A[0]:.2f}",
         "explanation": "the office doors the map adds to A (not named by the paper), and drift within the run",
         "experiment": "ablations, sensitivity",
         "numbers": f"only the paper's features: {named['trial 1']:.2f}; neighbour rate 0.05: {own['trial 1']:.2f}"},
        {"discrepancy": "the simulator's physics (run variation, noise, multipath, edges, inches)",
         "explanation": "not the main cause: one switch at a time moves trial 6 little; all four off "
                        "lower it to less than half, still an order of magnitude above the paper's",
         "experiment": "ablations",
         "numbers": f"one at a time: trial 6 x{min(singles):.2f}-{max(singles):.2f}; all four off: "
                    f"x{off['trial 6 / as simulated']:.2f}; off and only the paper's features: "
                    f"{stripped['trial 6']:.2f} ({stripped['trial 6'] / PAPER_A[5]:.0f}x the paper's)"},
        {"discrepancy": f"A*, B, C: {ratio} the paper's integrated novelty",
         "explanation": "they start from a model of A that has not settled (the same drift)",
         "experiment": "table1",
         "numbers": f"neighbour rate 0.05: {own_ratio}"},
        {"discrepancy": f"C's control 'far more' novel than C 1 on {c_control['holds on seeds']} seeds; "
                        f"'no other novel features' in A* on {nothing_else['holds on seeds']}",
         "explanation": "the same drift: the model of A is unsettled",
         "experiment": "table1",
         "numbers": f"neighbour rate 0.05: {c_control[OWN_HOLDS]} and {nothing_else[OWN_HOLDS]} seeds"},
        {"discrepancy": "maximum 0.42 (A 4, A 5, B 2, B 3, C 4)",
         "explanation": "the exact solution's third winner step; no count of unit Euler steps gives it",
         "experiment": "maxima",
         "numbers": f"exact: {m042['exact: winner steps only']}; Euler: {m042['euler: fewest steps']}"},
        {"discrepancy": "maximum 0.35 (B 4)",
         "explanation": "the third unit Euler winner step: Table 1 mixes both schemes' values",
         "experiment": "maxima",
         "numbers": f"Euler: {m035['euler: winner steps only']}; exact: {m035['exact: fewest steps']}"},
    ]
