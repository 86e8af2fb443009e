"""What ``novelty bench`` prints of a hold-out run: the columns a reader needs first, a verdict, where the rest is.

The table is rendered from the ranking's records
(:func:`novelty.bench.reports.ranking.rank_detectors`), the data of
``summary.md``'s ranking; every other column, the paired comparison and the
tests between detectors stay in ``summary.md``. Column headings are words, and
a line under the table says what ROC AUC measures.
"""

from __future__ import annotations

import math
from typing import Sequence

from ..bench.holdout.summary import any_route
from ..bench.reports.format import format_table, mean_spread, number
from ..bench.reports.ranking import RANK_BY, rank_detectors
from ..answers import FROZEN, PAPER
from ..bench.reports.statistics import statistics_line

__all__ = ["first_table", "columns_in_words", "verdict", "PAPERS_DETECTOR"]

#: the detector of Marsland, Nehmzow & Shapiro (2000), named in the verdict wherever it ran
PAPERS_DETECTOR = PAPER

#: (heading, column of the ranking's records, how it is shown, what it means)
_COLUMNS = [
    ("ROC AUC (± sd over seeds)", RANK_BY, None,
     "ROC AUC: how often a novel test scan scores above a familiar one (1: always, 0.5: chance), the mean "
     "over the tasks; every detector learned the training scans, then scored the test scans without learning."),
    ("caught at 5% false alarms", "tpr_at_5pct_fpr", "percent",
     "Caught: the share of novel scans above the threshold that 5% of the familiar test scans pass."),
    ("false alarms, clean pass", "false_alarms", 1,
     "False alarms: alarms raised on a clean pass of the route (or on the familiar test scans), at the "
     "threshold the training scans set."),
    ("learning (s)", "train_time_s", 2, "Learning: seconds to learn a task's training scans."),
]
_ROUTE_ONLY = {"false_alarms"}  # a route metric: shown when a task of the run has a route


def _shown(rows: Sequence[dict]) -> list[tuple]:
    return [c for c in _COLUMNS if c[1] not in _ROUTE_ONLY or any_route(rows)]


def columns_in_words(rows: Sequence[dict]) -> str:
    """What each column of :func:`first_table` measures, a sentence each."""
    return " ".join(c[3] for c in _shown(rows))


def _cell(record: dict, column: str, shown) -> str:
    value = record[column]
    if column == RANK_BY:
        return mean_spread(value, record[f"{RANK_BY}_sd"])
    if shown == "percent":
        return "-" if math.isnan(value) else f"{100 * value:.0f}%"
    return number(value, shown)


def first_table(rows: Sequence[dict]) -> str:
    """The detectors ranked, with the columns a newcomer reads first (and ``failed`` where a cell failed)."""
    columns = _shown(rows)
    records = rank_detectors(rows, [c[1] for c in columns if c[1] != RANK_BY])
    failed = any(r["failed"] for r in records)
    header = ["#", "detector", *(c[0] for c in columns)] + (["failed cells"] if failed else [])
    body = [[str(r["rank"]), r["detector"], *(_cell(r, column, shown) for _, column, shown, _ in columns)]
            + ([f"{r['failed']} of {r['cells']}"] if failed else []) for r in records]
    return format_table(header, body)


def _ordinal(n: int) -> str:
    """``n`` as a rank in words' order.

    >>> [_ordinal(n) for n in (1, 2, 3, 4, 11, 12, 21)]
    ['1st', '2nd', '3rd', '4th', '11th', '12th', '21st']
    """
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def verdict(rows: Sequence[dict]) -> str:
    """One line: which detector ranks first, where the answer of "Which detector?" for frozen detection
    (:data:`novelty.answers.FROZEN`) and the paper's detector rank, and what the ranking allows one to
    claim (Friedman's test over tasks, or why there is none).

    The ranks are by mean ROC AUC over tasks; the claim is
    :func:`~novelty.bench.reports.statistics.statistics_line`'s.
    """
    ranked = [r for r in rank_detectors(rows) if not math.isnan(r[RANK_BY])]
    if not ranked:
        return "Verdict: no detector was measured."
    first = ranked[0]
    text = f"Verdict: {first['detector']} ranks first (ROC AUC {number(first[RANK_BY])})"
    answer = next((r for r in ranked if r["detector"] == FROZEN), None)
    if answer is not None and answer is not first:
        text += (f"; {FROZEN}, the answer of \"Which detector?\" to learning a clean area and flagging what "
                 f"differs (measured on the whole detection suite), ranks {_ordinal(answer['rank'])} "
                 f"({number(answer[RANK_BY])})")
    paper = next((r for r in ranked if r["detector"] == PAPERS_DETECTOR), None)
    if paper is not None and paper is not first:
        text += (f"; the paper's {PAPERS_DETECTOR} ranks {_ordinal(paper['rank'])} of {len(ranked)} "
                 f"({number(paper[RANK_BY])})")
    return f"{text}. {statistics_line(rows)}"
