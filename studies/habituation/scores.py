"""The scores of the habituation study (studies/habituation/rule.md) from its runs.

    python studies/habituation/scores.py results/habituation-development-seen results/habituation-development-anywhere

Reads the runs' ``results.jsonl`` (or the ``results.csv`` committed beside this file) and prints, one line a candidate (its label) in the rule's order, H (the
``-familiar`` tasks, objects where the robot had looked before, on which it habituates: 3rd/1st excess
within +-0.25 with the first-exposure separation at least 0.5, as the exploration tables define it), its
first sight (the mean first-encounter ROC AUC of the ``-familiar`` tasks), its false alarms (the mean
false-alarm rate over every task), whether it passes the two guards against the control (``defaults``
unless ``--control`` says otherwise: first sight at least the control's minus 0.02, false alarms at most
the control's plus 0.01) and whether it meets the habituation bar (it habituates on every ``-familiar``
task); then the per-task figures. Each figure is a mean over the seeds the run holds, as
:func:`novelty.bench.exploration.summary.exploration_records` computes it.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np

from novelty.bench.exploration.summary import exploration_records
from novelty.bench.results import read_rows

LOGS = ("intel", "aces", "csail")
TASKS = tuple(f"exploration-objects-radish-{log}" for log in LOGS)
#: the places seen: the objects drawn where the robot had looked before they appear
SEEN = tuple(f"{task}-familiar" for task in TASKS)
#: how much first sight may fall below the control's, and false alarms rise above them
FIRST_SIGHT_MARGIN, FALSE_ALARM_MARGIN = 0.02, 0.01
#: item 6's first sight while learning, said beside the habituation bar
FIRST_SIGHT_BAR = 0.90


def read_results(folder) -> list[dict]:
    """The rows of a run's folder: its ``results.jsonl`` as ``novelty bench`` wrote it, else its ``results.csv``
    (the file committed beside this script; its values as text, which the scores read as numbers)."""
    folder = Path(folder)
    rows = read_rows(folder / "results.jsonl")
    if rows or not (folder / "results.csv").exists():
        return rows
    with open(folder / "results.csv", newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def scores(rows, control: str = "defaults") -> list[dict]:
    """One record per candidate, in the rule's order: both guards passed first, then H, then first sight, then label.

    A candidate missing a task (a failed or absent cell on every seed) has NaN figures there, which habituate on
    nothing and fail the guards.
    """
    by_task = {task: {r["detector"]: r for r in recs} for task, recs in exploration_records(rows).items()}
    candidates = sorted({d for recs in by_task.values() for d in recs})
    out = []
    for name in candidates:
        rec = {"candidate": name}
        cells = {task: by_task.get(task, {}).get(name) for task in TASKS + SEEN}
        for key in ("auc", "separation", "ratio", "excess_1", "excess_2", "excess_3", "false_alarm_rate"):
            rec[key] = {task: (c[key] if c else math.nan) for task, c in cells.items()}
        rec["habituates"] = {task: bool(c and c["habituates"]) for task, c in cells.items()}
        rec["H"] = sum(rec["habituates"][task] for task in SEEN)
        rec["first"] = float(np.mean([rec["auc"][task] for task in SEEN]))
        rec["false_alarms"] = float(np.mean(list(rec["false_alarm_rate"].values())))
        rec["bar"] = rec["H"] == len(SEEN)
        rec["first_at_bar"] = all(rec["auc"][task] >= FIRST_SIGHT_BAR for task in SEEN)
        out.append(rec)
    base = next((r for r in out if r["candidate"] == control), None)
    if base is None:
        raise ValueError(f"the control {control!r} is not among the run's candidates {candidates}")
    for rec in out:
        rec["first_stays"] = rec["first"] >= base["first"] - FIRST_SIGHT_MARGIN
        rec["not_flagged"] = rec["false_alarms"] <= base["false_alarms"] + FALSE_ALARM_MARGIN
        rec["guards"] = rec["first_stays"] and rec["not_flagged"]
    out.sort(key=lambda r: (not r["guards"], -r["H"], -np.nan_to_num(r["first"], nan=-1.0), r["candidate"]))
    return out


def _f(values, digits=3) -> str:
    return " / ".join("-" if math.isnan(v) else f"{v:.{digits}f}" for v in values)


def _yes(value: bool) -> str:
    return "yes" if value else "no"


def table(records) -> str:
    """The rule's table, then the per-task figures, as markdown."""
    short = "intel / aces / csail"
    head = ("| candidate | guards (first sight, false alarms) | H | first sight (familiar) | false alarms | bar |",
            "|---|---|---|---|---|---|")
    lines = list(head)
    for r in records:
        lines.append(f"| `{r['candidate']}` | {_yes(r['guards'])} ({_yes(r['first_stays'])}, {_yes(r['not_flagged'])}) "
                     f"| {r['H']} | {r['first']:.3f} | {r['false_alarms']:.3f} | {_yes(r['bar'])} |")
    lines += ["", f"Objects where the robot had looked before (`-familiar`), {short}:", "",
              "| candidate | first sight | separation | excess 1st | 2nd | 3rd | 3rd/1st | habituates |",
              "|---|---|---|---|---|---|---|---|"]
    lines += [_task_line(r, SEEN) for r in records]
    lines += ["", f"Objects anywhere beside the later path, {short}:", "",
              "| candidate | first sight | separation | excess 1st | 2nd | 3rd | 3rd/1st | habituates |",
              "|---|---|---|---|---|---|---|---|"]
    lines += [_task_line(r, TASKS) for r in records]
    return "\n".join(lines)


def _task_line(r, tasks) -> str:
    pick = lambda key: [r[key][t] for t in tasks]  # noqa: E731
    return (f"| `{r['candidate']}` | {_f(pick('auc'))} | {_f(pick('separation'), 2)} | {_f(pick('excess_1'))} "
            f"| {_f(pick('excess_2'))} | {_f(pick('excess_3'))} | {_f(pick('ratio'), 2)} "
            f"| {' / '.join(_yes(r['habituates'][t]) for t in tasks)} |")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="the runs' folders, as `novelty bench --out` wrote them")
    parser.add_argument("--control", default="defaults", help="the candidate the guards compare with")
    args = parser.parse_args(argv)
    rows = [row for run in args.runs for row in read_results(run)]
    if not rows:
        parser.error(f"no rows in {', '.join(args.runs)}: give the folders that `novelty bench --out` wrote")
    print(table(scores(rows, args.control)))


if __name__ == "__main__":
    main()
