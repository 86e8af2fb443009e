"""The ``summary.md`` of a run: the ranking, the paired comparison, the statistics and how it was made.

The ranking (detectors by the mean and spread over seeds of their ROC AUC
averaged over tasks, and the ROC AUC per task) is computed in
:mod:`novelty.bench.ranking`; the paired comparison with a reference
detector, the ranks per task and the tests between detectors in
:mod:`novelty.bench.significance`. Their public names are importable from
here too.
"""

from __future__ import annotations

import json
from typing import Sequence

from .ranking import (RANK_BY, _fmt, _in_order, _mean, _num, _pm, _sd, format_table,  # noqa: F401
                      per_task, per_task_text, rank_detectors, ranking_text, reference_of)
from .significance import (ALPHA, _p, _p_is, _signed, paired_text, statistics_line,  # noqa: F401
                           statistics_markdown, task_ranks_text)

__all__ = ["rank_detectors", "per_task", "format_table", "summary_markdown", "ranking_text",
           "paired_text", "reference_of", "task_ranks_text", "statistics_markdown", "statistics_line", "ALPHA"]


def summary_markdown(rows: Sequence[dict], title: str = "Benchmark", notes: Sequence[str] = (),
                     reference: str | None = None, run: dict | None = None) -> str:
    """The ``summary.md`` of a run.

    ``reference``: the detector of the paired comparison (default: the one
    ranked first); ``run``: how the run was made (``command``, ``versions``
    as JSON, ``git_revision``), recorded at the end.
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
        "## Ranking",
        "",
        "Ranked by ROC AUC averaged over tasks, mean ± standard deviation over seeds. Other columns "
        "are means over cells: average precision, true-positive rate at 1% and 5% false-positive "
        "rate, detection delay in scans (first novel scan to first alarm, at a threshold set from the "
        "training novelty only: its maximum unless a note below says otherwise), false alarms on a "
        "clean pass (or the normal test scans), integrated "
        "novelty over the test part with the resting activity subtracted and its maximum, "
        "training time, peak memory (MiB, traced), model size in units.",
        "",
        ranking_text(rows),
        *_paired_section(rows, reference),
        "",
        "## ROC AUC per task",
        "",
        "Mean ± standard deviation over seeds.",
        "",
        per_task_text(rows),
        "",
        "## Ranks per task",
        "",
        "Rank of each detector on each task by its mean ROC AUC over seeds (1 = best, ties share the "
        "average rank), and the average over tasks.",
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
        f"Each detector's ROC AUC minus {chosen}'s on the same cell (same task, same seed), over "
        f"the cells both completed: mean ± standard error of the differences (positive: better "
        f"than {chosen}), the cells won, tied and lost, and the Holm-adjusted p-value of the "
        f"Wilcoxon signed-rank test of the pair (see Statistics). The reference is {how}",
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
