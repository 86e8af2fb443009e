"""The ``summary.md`` of a run: the protocol's tables, the paired comparison, the statistics and how it was made.

The protocol's own sections come first (the hold-out ranking, or the
exploration tables); then the ROC AUC per task
(:mod:`novelty.bench.reports.ranking`), the paired comparison with a
reference detector, the ranks per task and the tests between detectors
(:mod:`novelty.bench.reports.statistics`), and how the run was made.
"""

from __future__ import annotations

import json
from typing import Sequence

from ..stats.bayesian import ROPE
from .ranking import reference_of
from .statistics import paired_text, seeds_text, statistics_markdown, task_ranks_text

__all__ = ["summary_markdown"]


def summary_markdown(rows: Sequence[dict], title: str = "Benchmark", notes: Sequence[str] = (),
                     reference: str | None = None, run: dict | None = None,
                     sections: Sequence[str] = ()) -> str:
    """The ``summary.md`` of a run.

    ``reference``: the detector of the paired comparison (default: the one
    ranked first); ``run``: how the run was made (``command``, ``versions``
    as JSON, ``git_revision``), recorded at the end; ``sections``: the
    protocol's own sections (markdown lines), after the count of cells.
    """
    rows = list(rows)
    seeds = sorted({r["seed"] for r in rows})
    failed = [r for r in rows if r.get("status") != "ok"]
    parts = [
        f"# {title}",
        "",
        f"{len(rows)} cells: {len({r['detector'] for r in rows})} detectors x "
        f"{len({r['task'] for r in rows})} tasks x {len(seeds)} seeds ({', '.join(map(str, seeds))}); "
        f"{len(failed)} failed.",
        "",
        *sections,
        *_paired_section(rows, reference),
        "",
        "## ROC AUC per task",
        "",
        "Unit: the seed within a task. Mean over seeds and its 95% confidence interval (Student t over "
        "the seeds); '1 value' where the seeds repeated one measurement.",
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
    if failed:
        parts += ["", "## Failed cells", ""]
        parts += [f"- {r['detector']} / {r['task']} / seed {r['seed']}: {r.get('error', '')}" for r in failed]
    if notes:
        parts += ["", "## Notes", "", *(f"- {n}" for n in notes)]
    parts += ["", "## How this run was made", "", *_provenance_lines(rows, run or {})]
    return "\n".join(parts) + "\n"


def _paired_section(rows: Sequence[dict], reference: str | None) -> list[str]:
    chosen = reference_of(rows, reference)
    if chosen is None:
        return []
    how = ("the suite's `reference`." if reference is not None else
           "the detector ranked first (set `reference` in the suite or `--reference` to choose).")
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
