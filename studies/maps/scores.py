"""The scores of the fourth to seventh selections of habituating maps (studies/maps/maps-round4.md,
maps-round5.md, maps-round6.md, maps-round7.md) from their runs.

    python studies/maps/scores.py --inspection results/maps-round4-inspection \
        --exploration results/maps-round4-exploration --guard results/maps-round4-detection

Reads the three runs' ``results.jsonl`` and prints, one line a candidate (its label), in the rule's order:
G (passes the guard: mean ROC AUC > 0.5 on every task of the guard run), F, H and S as maps-round3.md
defines them (F: first-encounter AUC >= 0.90 with separation >= 0.5 on an ``exploration-objects-radish-*``
task; until round 6 the scorer took the tables' "flags", AUC >= 0.85, and every candidate of rounds 4-5
had F = 0 either way, first sight at most 0.787; H: 3rd/1st within +-0.25 with separation >= 0.5 on intel
and aces; S: the mean of the three inspection ROC AUCs and the three first-encounter AUCs), then the
per-task figures. With ``--familiar`` (the sixth selection) the exploration tasks are six: the three logs
and the same with the objects where the robot had looked before (``-familiar``); F counts the six, H
intel, aces, intel-familiar and csail-familiar (aces-familiar's objects are passed twice), S averages
nine. ``--guard-above`` sets G's threshold (the seventh selection's margin: 0.55; until then 0.5).
``--alias CANDIDATE=RUN`` scores an exploration-only candidate with RUN's hold-out cells (the occupancy
grid's frozen forms, studies/maps/maps-grid.md).
Every score is a mean over the seeds each run holds; a candidate with a missing or failed cell is
reported as such and ranked last.
"""

from __future__ import annotations

import argparse
import math
from collections import defaultdict

import numpy as np

from novelty.bench.exploration.metrics import SEPARATES
from novelty.bench.exploration.summary import exploration_records
from novelty.bench.results import read_rows

LOGS = ("intel", "aces", "csail")
#: F's first-encounter AUC: the bar's (the tables' "flags" take 0.85, FLAGS_FIRST)
BAR = 0.90


def task_means(rows, metric: str) -> dict:
    """``{(detector, task): mean of metric over the seeds}``; NaN where a cell failed."""
    cells = defaultdict(list)
    for r in rows:
        cells[(r["detector"], r["task"])].append(float(r[metric]) if r.get("status") == "ok" else math.nan)
    return {k: float(np.mean(v)) for k, v in cells.items()}


def scores(inspection, exploration, guard, familiar: bool = False, guard_above: float = 0.5) -> list[dict]:
    """One record per candidate, ordered by the rule: G (mean ROC AUC above ``guard_above`` on every guard task),
    then F + H, then S."""
    tasks = [f"exploration-objects-radish-{log}" for log in LOGS]
    habituation = tasks[:2]
    if familiar:
        tasks += [f"{t}-familiar" for t in tasks]
        habituation += [f"{tasks[0]}-familiar", f"{tasks[2]}-familiar"]
    insp, gd = task_means(inspection, "roc_auc"), task_means(guard, "roc_auc")
    expl = {task: {r["detector"]: r for r in recs} for task, recs in exploration_records(exploration).items()}
    guard_tasks = sorted({t for _, t in gd})
    out = []
    for det in sorted({d for d, _ in insp}):
        rec = {"candidate": det}
        rec["inspection"] = [insp.get((det, f"inspection-objects-radish-{log}"), math.nan) for log in LOGS]
        ex = [expl.get(t, {}).get(det) for t in tasks]
        hab = [expl.get(t, {}).get(det) for t in habituation]
        rec["first"] = [e["auc"] if e else math.nan for e in ex]
        rec["separation"] = [e["separation"] if e else math.nan for e in ex]
        rec["ratio"] = [e["ratio"] if e else math.nan for e in hab]
        rec["F"] = sum(bool(e and e["auc"] >= BAR and e["separation"] >= SEPARATES) for e in ex)
        rec["H"] = sum(bool(e and e["habituates"]) for e in hab)
        rec["S"] = float(np.mean(rec["inspection"] + rec["first"]))
        rec["guard"] = {t: gd.get((det, t), math.nan) for t in guard_tasks}
        rec["G"] = bool(guard_tasks) and all(v > guard_above for v in rec["guard"].values())
        out.append(rec)
    out.sort(key=lambda r: (not r["G"], -(r["F"] + r["H"]), -np.nan_to_num(r["S"], nan=-1.0), r["candidate"]))
    return out


def _f(values, digits=3) -> str:
    return " / ".join("-" if math.isnan(v) else f"{v:.{digits}f}" for v in values)


def table(records, familiar: bool = False) -> str:
    """The selection's table, as markdown."""
    logs = "intel / aces / csail" + (" / the same, familiar" if familiar else "")
    ratios = "intel / aces / intel-familiar / csail-familiar" if familiar else "intel / aces"
    head = (f"| candidate | guard | F | H | S | inspection intel / aces / csail | first sight {logs} "
            f"| separation {logs} | 3rd/1st {ratios} | guard ROC AUC (" +
            (" / ".join(records[0]["guard"]) if records else "") + ") |")
    lines = [head, "|" + "---|" * 10]
    for r in records:
        lines.append(f"| `{r['candidate']}` | {'pass' if r['G'] else 'fail'} | {r['F']} | {r['H']} | {r['S']:.3f} | "
                     f"{_f(r['inspection'])} | {_f(r['first'])} | {_f(r['separation'], 2)} | {_f(r['ratio'], 2)} | "
                     f"{_f(list(r['guard'].values()))} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name in ("inspection", "exploration", "guard"):
        parser.add_argument(f"--{name}", required=True, help=f"the {name} run's folder (its results.jsonl)")
    parser.add_argument("--familiar", action="store_true",
                        help="the sixth selection's six exploration tasks (the logs and their -familiar twins)")
    parser.add_argument("--guard-above", type=float, default=0.5,
                        help="G's threshold on every guard task's mean ROC AUC (the seventh selection's: 0.55)")
    parser.add_argument("--alias", action="append", default=[], metavar="CANDIDATE=RUN",
                        help="a candidate of the exploration run whose hold-out cells are RUN's (a form frozen "
                             "after the warm-up is, on the hold-out tasks, the learning form: maps-grid.md)")
    args = parser.parse_args(argv)
    rows = {name: read_rows(f"{getattr(args, name)}/results.jsonl") for name in ("inspection", "exploration", "guard")}
    for alias in args.alias:
        candidate, _, same = alias.partition("=")
        for name in ("inspection", "guard"):
            rows[name] += [{**r, "detector": candidate} for r in rows[name] if r["detector"] == same]
    empty = [f"{getattr(args, name)}/results.jsonl" for name, found in rows.items() if not found]
    if empty:
        parser.error(f"no rows in {', '.join(empty)}: give the folders that `novelty bench --out` wrote")
    print(table(scores(rows["inspection"], rows["exploration"], rows["guard"], args.familiar, args.guard_above),
                args.familiar))


if __name__ == "__main__":
    main()
