"""The paper's Table 1, and ours beside it: rows, markdown and CSV.

Shares its name with ``novelty/reproduce/experiments/table1.py``: the paper's Table 1: its
experiments, and its rows beside the paper's.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

from .trial import Trial

__all__ = ["PAPER_TABLE1", "TABLE1_COLUMNS", "table1_rows", "table1_markdown", "write_table1_csv",
           "write_table1_markdown"]

#: The paper's Table 1: (experiment, trial, mode, integrated, maximum).
PAPER_TABLE1: tuple[tuple[str, str, str, float, float], ...] = (
    ("A", "1", "L", 9.17, 1.00),
    ("A", "2", "NL", 2.64, 0.53),
    ("A", "3", "L", 1.34, 0.43),
    ("A", "4", "NL", 1.07, 0.42),
    ("A", "5", "L", 0.52, 0.42),
    ("A", "6", "NL", 0.30, 0.12),
    ("A*", "1", "NL", 1.44, 0.65),
    ("A*", "2", "L", 1.45, 0.65),
    ("A*", "3", "NL", 0.37, 0.17),
    ("A*", "4", "L", 0.14, 0.08),
    ("A*", "5", "NL", 0.01, 0.05),
    ("B", "1", "NL", 3.38, 0.65),
    ("B", "2", "L", 1.18, 0.42),
    ("B", "3", "NL", 1.21, 0.42),
    ("B", "4", "L", 0.87, 0.35),
    ("B", "5", "NL", 0.03, 0.08),
    ("B", "Control", "NL", 27.09, 1.00),
    ("C", "1", "NL", 9.68, 0.65),
    ("C", "2", "L", 2.56, 0.65),
    ("C", "3", "NL", 3.06, 0.53),
    ("C", "4", "L", 0.98, 0.42),
    ("C", "5", "NL", 0.29, 0.15),
    ("C", "Control", "NL", 27.75, 1.00),
)

TABLE1_COLUMNS = ("experiment", "trial", "mode", "integrated", "maximum", "paper_integrated", "paper_maximum")


def table1_rows(trials: list[Trial]) -> list[dict]:
    """Table 1 rebuilt, one dict per trial, beside the paper's values (NaN where it has none)."""
    paper = {(e, t): (i, m) for e, t, _, i, m in PAPER_TABLE1}
    rows = []
    for tr in trials:
        p_int, p_max = paper.get((tr.experiment, tr.trial), (float("nan"), float("nan")))
        rows.append({"experiment": tr.experiment, "trial": tr.trial, "mode": tr.mode,
                     "integrated": round(tr.integrated, 2), "maximum": round(tr.maximum, 2),
                     "paper_integrated": p_int, "paper_maximum": p_max})
    return rows


def _cell(value: float) -> str:
    return "—" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{value:.2f}"


def table1_markdown(rows: list[dict]) -> str:
    """Table 1 as a markdown table, ours beside the paper's."""
    lines = ["| Exp (Env) | Trial | Integrated | Maximum | Paper integrated | Paper maximum |",
             "| --- | --- | ---: | ---: | ---: | ---: |"]
    for r in rows:
        label = r["trial"] if r["trial"] == "Control" else f"{r['trial']} ({r['mode']})"
        lines.append(f"| {r['experiment']} | {label} | {_cell(r['integrated'])} | {_cell(r['maximum'])} | "
                     f"{_cell(r['paper_integrated'])} | {_cell(r['paper_maximum'])} |")
    return "\n".join(lines)


def write_table1_csv(rows: list[dict], path: str | Path) -> None:
    """``table1.csv``: one row per trial; the paper's columns are empty where it has no value."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=TABLE1_COLUMNS)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: ("" if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()})


def write_table1_markdown(rows: list[dict], path: str | Path, title: str | None = None) -> None:
    text = table1_markdown(rows) + "\n"
    if title:
        text = f"{title}\n\n{text}"
    Path(path).write_text(text, encoding="utf-8")
