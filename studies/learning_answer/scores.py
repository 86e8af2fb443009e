"""The scores of the rule that answers "a robot that keeps learning" (studies/learning_answer/learning-answer.md).

    python studies/learning_answer/scores.py --exploration results/la-ring results/la-points \
        --guard results/la-guard-ring results/la-guard-points

Reads the runs' ``results.jsonl`` and prints, one line a candidate in the rule's order: G (mean ROC AUC
above 0.5 on every hold-out task of its guard run, on the selection's guard seeds 105-109 and on the
reported guard seeds 5-9, each set averaged alone), B (the exploration tasks on which it both flags and
habituates), V (the verdicts met: flags, habituates), S (the mean first-encounter ROC AUC over the
tasks), then the per-task figures; and the decision of step 2: the answer changes from the incumbent
(``explore``) only to a candidate ahead of it. The verdicts are the tables' own
(:func:`novelty.bench.exploration.summary.exploration_records`). A task a candidate has no verdict on
(its cells failed or were not run) counts as no verdict and NaN in S.

With ``--must-pass`` (the rule of learning-answer-no-pose.md, for a robot without a pose) there is no
incumbent: the answer is the first candidate in order if it passes G, and none otherwise.
"""

from __future__ import annotations

import argparse
import math
from collections import defaultdict

import numpy as np

from novelty.bench.exploration.summary import exploration_records
from novelty.bench.results import read_rows

INCUMBENT = "explore"
#: the guard's seed sets: the selection's and the ones the guides report
GUARD_SEEDS = {"105-109": range(105, 110), "5-9": range(5, 10)}
#: how far ahead on S a candidate level on G, B and V must be to replace the incumbent
S_MARGIN = 0.01


def guard_means(rows) -> dict:
    """``{(detector, seeds, task): mean ROC AUC}`` per guard seed set; NaN where a cell failed."""
    cells = defaultdict(list)
    for r in rows:
        for name, seeds in GUARD_SEEDS.items():
            if int(r["seed"]) in seeds:
                ok = r.get("status") == "ok"
                cells[(r["detector"], name, r["task"])].append(float(r["roc_auc"]) if ok else math.nan)
    return {k: float(np.mean(v)) for k, v in cells.items()}


def scores(exploration, guard) -> list[dict]:
    """One record per candidate (a detector of the exploration rows), unordered."""
    verdicts = exploration_records(exploration)
    tasks = sorted({r["task"] for r in exploration})
    by_task = {t: {rec["detector"]: rec for rec in verdicts.get(t, [])} for t in tasks}
    gm = guard_means(guard)
    out = []
    for det in sorted({r["detector"] for r in exploration}):
        found = [by_task[t].get(det) for t in tasks]
        rec = {"candidate": det, "tasks": tasks}
        rec["first"] = [f["auc"] if f else math.nan for f in found]
        rec["ratio"] = [f["ratio"] if f else math.nan for f in found]
        rec["separation"] = [f["separation"] if f else math.nan for f in found]
        rec["flags"] = [bool(f and f["flags"]) for f in found]
        rec["habituates"] = [bool(f and f["habituates"]) for f in found]
        rec["B"] = sum(bool(f and f["both"]) for f in found)
        rec["V"] = sum(rec["flags"]) + sum(rec["habituates"])
        rec["S"] = float(np.mean(rec["first"]))
        rec["guard"] = {(s, t): v for (d, s, t), v in sorted(gm.items()) if d == det}
        seen = {s for s, _ in rec["guard"]}
        rec["G"] = seen == set(GUARD_SEEDS) and all(v > 0.5 for v in rec["guard"].values())
        out.append(rec)
    return out


def _key(rec) -> tuple:
    return (not rec["G"], -rec["B"], -rec["V"], -np.nan_to_num(rec["S"], nan=-1.0))


def ordered(records) -> list[dict]:
    """Step 1: those that pass G first, then B, then V (more first), then S (higher first)."""
    return sorted(records, key=lambda r: (*_key(r), r["candidate"] != INCUMBENT, r["candidate"]))


def ahead(candidate: dict, incumbent: dict) -> bool:
    """Step 2: ``candidate`` is ahead of the incumbent on G, or level and ahead on B, then V, then S by S_MARGIN."""
    for mine, theirs in zip(_key(candidate)[:3], _key(incumbent)[:3]):
        if mine != theirs:
            return mine < theirs
    return candidate["S"] >= incumbent["S"] + S_MARGIN


def answer(records) -> str:
    """The answer the rule gives: the first in order if it is ahead of the incumbent, else the incumbent."""
    first = ordered(records)[0]
    incumbent = next((r for r in records if r["candidate"] == INCUMBENT), None)
    if incumbent is None or first is incumbent:
        return INCUMBENT if incumbent is not None else first["candidate"]
    return first["candidate"] if ahead(first, incumbent) else INCUMBENT


def answer_that_passes(records) -> str | None:
    """learning-answer-no-pose.md's answer: the first in order if it passes the guard, else None."""
    first = ordered(records)[0] if records else None
    return first["candidate"] if first is not None and first["G"] else None


def _f(values, digits=3) -> str:
    return " / ".join("-" if math.isnan(v) else f"{v:.{digits}f}" for v in values)


def _short(task: str) -> str:
    return task.removeprefix("exploration-").removeprefix("objects-radish-")


def table(records) -> str:
    """The rule's table, as markdown: the scores, then first sight, 3rd/1st and the verdicts per task."""
    recs = ordered(records)
    tasks = " / ".join(_short(t) for t in recs[0]["tasks"]) if recs else ""
    lines = [f"| candidate | G | B | V | S | first sight ({tasks}) | 3rd/1st | flags | habituates | lowest guard mean |",
             "|" + "---|" * 10]
    for r in recs:
        def where(key, r=r):
            return ", ".join(_short(t) for t, v in zip(r["tasks"], r[key]) if v) or "none"
        worst = min(r["guard"].items(), key=lambda kv: kv[1]) if r["guard"] else None
        low = f"{worst[1]:.3f} ({worst[0][1]}, seeds {worst[0][0]})" if worst else "-"
        lines.append(f"| `{r['candidate']}` | {'pass' if r['G'] else 'fail'} | {r['B']} | {r['V']} | {r['S']:.3f} | "
                     f"{_f(r['first'])} | {_f(r['ratio'], 2)} | {where('flags')} | {where('habituates')} | {low} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exploration", nargs="+", required=True, help="the exploration runs' folders")
    parser.add_argument("--guard", nargs="+", required=True, help="the guard runs' folders")
    parser.add_argument("--must-pass", action="store_true",
                        help="no incumbent: the first in order if it passes the guard, else none "
                             "(learning-answer-no-pose.md)")
    args = parser.parse_args(argv)
    runs = {d: read_rows(f"{d}/results.jsonl") for d in [*args.exploration, *args.guard]}
    empty = [d for d, rows in runs.items() if not rows]
    if empty:
        parser.error(f"no rows in {', '.join(f'{d}/results.jsonl' for d in empty)}: give the folders that "
                     "`novelty bench --out` wrote")
    exploration = [r for d in args.exploration for r in runs[d]]
    guard = [r for d in args.guard for r in runs[d]]
    records = scores(exploration, guard)
    print(table(records))
    if args.must_pass:
        found = answer_that_passes(records)
        print("\nThe rule's answer: " + (f"`{found}`." if found else "none (no candidate passes the guard)."))
    else:
        print(f"\nThe rule's answer: `{answer(records)}`.")


if __name__ == "__main__":
    main()
