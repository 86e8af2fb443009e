"""The ``summary.md`` of a run: the protocol's tables, the paired comparison, the statistics and how it was made.

The protocol's own sections come first (the hold-out ranking, or the
exploration tables); then the ROC AUC per task
(:mod:`novelty.bench.reports.ranking`), the paired comparison with a
reference detector, the ranks per task and the tests between detectors
(:mod:`novelty.bench.reports.statistics`), and how the run was made.

Shares its name with ``novelty/bench/exploration/summary.py``, ``novelty/bench/holdout/summary.py``,
``novelty/reproduce/experiments/summary.py``: each benchmark protocol's package holds its own
metrics, plots and summary; the reports and the paper's experiments summarise a run of theirs.
"""

from __future__ import annotations

import json
from typing import Sequence

from ..._markup import counted
from ..stats.bayesian import ROPE
from .format import format_table
from .ranking import reference_of
from .statistics import paired_text, seeds_text, statistics_markdown, task_ranks_text

__all__ = ["summary_markdown", "warning_counts", "warnings_note"]


def summary_markdown(rows: Sequence[dict], title: str = "Benchmark", notes: Sequence[str] = (),
                     reference: str | None = None, run: dict | None = None,
                     sections: Sequence[str] = (), reference_how: str | None = None) -> str:
    """The ``summary.md`` of a run.

    ``reference``: the detector of the paired comparison (default: the first
    by label), ``reference_how`` how it was chosen; ``run``: how the run was made (``command``, ``versions``
    as JSON, ``git_revision``), recorded at the end; ``sections``: the
    protocol's own sections (markdown lines), after the count of cells.
    """
    rows = list(rows)
    seeds = sorted({r["seed"] for r in rows})
    failed = [r for r in rows if r.get("status") != "ok"]
    parts = [
        f"# {title}",
        "",
        f"{counted(len(rows), 'cell')}: {counted(len({r['detector'] for r in rows}), 'detector')} x "
        f"{counted(len({r['task'] for r in rows}), 'task')} x {counted(len(seeds), 'seed')} "
        f"({', '.join(map(str, seeds))}); {len(failed)} failed.",
        "",
        *sections,
        *_paired_section(rows, reference, reference_how),
        "",
        "## ROC AUC per task",
        "",
        "Unit: the seed within a task. Mean over seeds and its 95% confidence interval (Student t over "
        "the seeds, truncated to [0, 1], where ROC AUC lies); '1 value' where the seeds repeated one "
        "measurement.",
        "",
        seeds_text(rows),
        "",
        "## Ranks per task",
        "",
        "Unit: the task. Rank of each detector on each task by its mean ROC AUC over seeds (1 = best, "
        "ties share the average rank), and the average over tasks.",
        "",
        task_ranks_text(rows),
        "",
        "## Statistics",
        "",
        *statistics_markdown(rows),
    ]
    parts += _warnings_section(rows)
    if failed:
        parts += ["", "## Failed cells", ""]
        parts += [f"- {r['detector']} / {r['task']} / seed {r['seed']}: {r.get('error', '')}" for r in failed]
    if notes:
        parts += ["", "## Notes", "", *(f"- {n}" for n in notes)]
    parts += ["", "## How this run was made", "", *_provenance_lines(rows, run or {})]
    return "\n".join(parts) + "\n"


def _paired_section(rows: Sequence[dict], reference: str | None, how: str | None = None) -> list[str]:
    chosen = reference_of(rows, reference)
    if chosen is None:
        return []
    how = how or ("the given `reference`." if reference is not None else
                  "the first detector by label (set `reference` in the suite or `--reference` to choose).")
    return [
        "",
        f"## Paired comparison with {chosen}",
        "",
        f"Unit: the task. Each detector's ROC AUC minus {chosen}'s on the same task (each the mean "
        f"over its seeds), over the tasks both completed: mean ± standard error of the differences "
        f"(positive: better than {chosen}), the tasks won, tied and lost, the Holm-adjusted p-value "
        f"of the exact Wilcoxon signed-rank test of the pair (see Statistics), and the Bayesian "
        f"signed-rank test's probabilities that the detector is practically worse than, equivalent "
        f"to or better than {chosen} (Benavoli et al. 2017; equivalent: within ± {ROPE} ROC AUC). "
        f"The reference is {how}",
        "",
        paired_text(rows, chosen),
    ]


def _categories(row: dict) -> list[str]:
    """The warning categories a row records (``warning_types``, or read from ``warnings`` in older rows)."""
    types = row.get("warning_types")
    if types:
        return str(types).split(",")
    text = row.get("warnings") or ""
    return sorted({part.split(":", 1)[0].strip() for part in str(text).split(" | ") if ":" in part})


def warning_counts(rows: Sequence[dict]) -> dict[str, tuple[int, str]]:
    """``{category: (cells that raised it, the first message)}`` over every cell, categories sorted."""
    found: dict[str, list] = {}
    for row in rows:
        messages = [m for m in str(row.get("warnings") or "").split(" | ") if m]
        for category in _categories(row):
            entry = found.setdefault(category, [0, ""])
            entry[0] += 1
            entry[1] = entry[1] or next((m for m in messages if m.startswith(category + ":")), "")
    return {c: (n, m) for c, (n, m) in sorted(found.items())}


def warnings_note(rows: Sequence[dict]) -> str | None:
    """One line for the console: which warnings were raised in how many cells (None: none were)."""
    counts = warning_counts(rows)
    if not counts:
        return None
    cells = sum(1 for r in rows if _categories(r))
    named = ", ".join(f"{c} in {n}" for c, (n, _) in counts.items())
    return (f"Warnings were raised in {cells} of {len(rows)} cells ({named}); they can change results "
            "(summary.md, Warnings raised in cells, quotes each).")


def _warnings_section(rows: Sequence[dict]) -> list[str]:
    counts = warning_counts(rows)
    if not counts:
        return []
    return ["", "## Warnings raised in cells", "",
            "Warnings raised while a cell ran (a ScanRangeWarning, for one, says that inputs lie outside the "
            "range a clusterer assumes, which changes its results): the cells that raised each kind, and its "
            "first message.", "",
            format_table(["warning", "cells", "first message"],
                         [[c, str(n), m[:160]] for c, (n, m) in counts.items()])]


def _provenance_lines(rows: Sequence[dict], run: dict) -> list[str]:
    lines = []
    if run.get("command"):
        lines.append(f"- command: `{run['command']}`")
    if run.get("versions"):
        versions = json.loads(run["versions"])
        lines.append("- versions: " + ", ".join(f"{k} {v}" for k, v in sorted(versions.items())))
    if run.get("git_revision"):
        lines.append(f"- revision: {run['git_revision']}")
    older = sorted({str(r.get("git_revision") or "unknown") for r in rows if "versions" in r}
                   - {run.get("git_revision")})
    if older:
        lines.append(f"- cells from earlier runs were computed at revision {', '.join(older)}")
    return lines or ["- not recorded"]
