"""The exploration table: which detectors flag first encounters, and which habituate.

One table per task, one line per detector, values over seeds: the
first-encounter ROC AUC (mean ± sd), the excess novelty over familiar scans
at a recurring feature's 1st, 2nd and 3rd exposure (means), their ratio
(mean excess at the 3rd over mean excess at the 1st), exposures to habituate
(mean over the features that did; the share that did in brackets), the
false-alarm rate, re-detection ROC AUC, the return ratio and the
first-exposure separation (median over seeds). A detector *flags* first
encounters when its mean AUC is at least 0.85, and *habituates* when the
ratio lies within 0.25 of 0 (either side of the familiar level; no ratio
unless the mean 1st excess is above a millionth of the detector's mean
range of novelty), each only with a separation of at least 0.5
(:mod:`novelty.bench.exploration.metrics`); the verdicts without the
separation stay in two columns of their own.

Shares its name with ``novelty/bench/holdout/summary.py``, ``novelty/bench/reports/summary.py``,
``novelty/reproduce/experiments/summary.py``: each benchmark protocol's package holds its own
metrics, plots and summary; the reports and the paper's experiments summarise a run of theirs.
"""

from __future__ import annotations

import math
from collections import defaultdict
from typing import Sequence

import numpy as np

from ..reports.format import format_table, number, yes_no
from ..stats.aggregate import as_float, mean, sd
from .metrics import FLAGS_FIRST, HABITUATED, RESOLUTION, SEPARATES, habituated, ratio_to_first

__all__ = ["exploration_records", "exploration_text", "exploration_markdown"]


def exploration_records(rows: Sequence[dict]) -> dict[str, list[dict]]:
    """``{task: [record per detector]}`` from the successful exploration rows, best first."""
    groups: dict[str, dict[str, list[dict]]] = defaultdict(lambda: defaultdict(list))
    for row in sorted(rows, key=lambda r: (str(r["task"]), str(r["detector"]), r["seed"])):
        if row.get("status") == "ok" and row.get("policy"):
            groups[row["task"]][row["detector"]].append(row)
    out = {}
    for task, by_detector in groups.items():
        records = []
        for detector, cells in by_detector.items():
            col = lambda name, cells=cells: [as_float(r.get(name)) for r in cells]  # noqa: E731
            auc, e1, e3 = mean(col("first_encounter_auc")), mean(col("excess_1")), mean(col("excess_3"))
            # rows recorded before the range was measured carry none: the ratio then needs e1 > 0 only
            ratio = ratio_to_first(e3, e1, RESOLUTION * np.nan_to_num(mean(col("novelty_range"))))
            separation = _median(col("first_separation"))
            # rows recorded before the separation was measured carry none: no veto then
            separates = separation >= SEPARATES or math.isnan(separation)
            flags, habituates = auc >= FLAGS_FIRST and separates, habituated(ratio) and separates
            records.append({
                "detector": detector, "policy": cells[0]["policy"], "seeds": len(cells),
                "auc": auc, "auc_sd": sd(col("first_encounter_auc")),
                "excess_1": e1, "excess_2": mean(col("excess_2")), "excess_3": e3, "ratio": ratio,
                "to_habituate": mean(col("exposures_to_habituate")),
                "habituated_fraction": mean(col("habituated_fraction")),
                "false_alarm_rate": mean(col("false_alarm_rate")),
                "redetection_auc": mean(col("redetection_auc")),
                "return_ratio": mean(col("return_ratio")),
                "separation": separation,
                "flags_auc_only": auc >= FLAGS_FIRST, "habituates_ratio_only": habituated(ratio),
                "flags": flags, "habituates": habituates, "both": flags and habituates,
            })
        records.sort(key=lambda r: (not r["both"], not r["flags"], -np.nan_to_num(r["auc"]), r["detector"]))
        out[task] = records
    return out


def _median(values: list) -> float:
    values = [v for v in values if not math.isnan(v)]
    return float(np.median(values)) if values else float("nan")


def _separation(value: float) -> str:
    if math.isnan(value):
        return "-"
    return "> 100" if value > 100 else f"{value:.2f}"


def exploration_text(rows: Sequence[dict]) -> str:
    """The exploration tables, one a task, as markdown."""
    parts = []
    header = ["detector", "first-encounter AUC", "excess 1st", "2nd", "3rd", "3rd/1st",
              "exposures to habituate", "false alarms", "re-detection AUC", "return ratio", "separation",
              "flags", "habituates", "both", "AUC >= 0.85", "ratio within ±0.25"]
    for task, records in exploration_records(rows).items():
        body = [[
            r["detector"], number(r["auc"]) + ("" if math.isnan(r["auc_sd"]) else f" ± {number(r['auc_sd'])}"),
            number(r["excess_1"]), number(r["excess_2"]), number(r["excess_3"]), number(r["ratio"], 2),
            "-" if math.isnan(r["to_habituate"]) else
            f"{r['to_habituate']:.1f} ({r['habituated_fraction']:.0%})",
            number(r["false_alarm_rate"]), number(r["redetection_auc"]), number(r["return_ratio"], 2),
            _separation(r["separation"]),
            yes_no(r["flags"]), yes_no(r["habituates"]), yes_no(r["both"]),
            yes_no(r["flags_auc_only"]), yes_no(r["habituates_ratio_only"]),
        ] for r in records]
        seeds = sorted({r["seed"] for r in rows if r["task"] == task})
        parts += [f"### {task} (seeds {', '.join(map(str, seeds))})", "", format_table(header, body), ""]
    return "\n".join(parts).rstrip() + "\n"


def exploration_markdown(rows: Sequence[dict]) -> list[str]:
    """The exploration section of ``summary.md`` (no lines when no row is of that protocol)."""
    if not exploration_records(rows):
        return []
    return [
        "## Exploration: first encounters and habituation", "",
        "Every scan scored, then learned, in order (policy in the label: online, frozen after the "
        "warm-up, refit after every run, or on a sliding window of runs). First-encounter AUC: "
        "scans at a tracked feature's first exposure against the familiar scans of the same runs "
        "(mean ± sd over seeds). Excess: the novelty of a recurring feature (met at least three "
        "times) above the familiar scans of the same run, at its 1st, 2nd and 3rd exposure. "
        f"Separation: the median first-exposure scan's novelty above the familiar scans' median, in "
        f"familiar interquartile ranges (median over seeds). A detector flags first encounters when "
        f"the AUC is at least {FLAGS_FIRST} and the separation at least {SEPARATES}, and habituates "
        f"when the 3rd excess lies within {HABITUATED} of the 1st of the familiar level, either side "
        f"(no ratio when the 1st is not above the detector's resolution), and the separation is at least "
        f"{SEPARATES}; the last two columns keep the verdicts without the separation. Return ratio: "
        "the excess of a feature back after a long absence over its first excess. Exposures to habituate: the first "
        f"exposure with an excess within {HABITUATED} of the first one, mean over the features that "
        "got there (the share that did). False alarms: the share of familiar scans above the "
        "maximum novelty of the last warm-up run. Re-detection: a known place that changes again, "
        "its first exposure against the familiar scans of its run.",
        "", exploration_text(rows).rstrip(),
    ]
