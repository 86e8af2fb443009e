"""Reading result rows as numbers: one value a cell, means and spreads over seeds.

Rows come from ``results.jsonl``/``results.csv`` (a missing or empty value is
NaN) and from backends that finish cells in any order: :func:`in_order` sorts
them so that every sum is taken in one order and a table is identical
whichever backend ran it.
"""

from __future__ import annotations

import math
from typing import Iterable, Sequence

import numpy as np

__all__ = ["as_float", "in_order", "mean", "sd"]


def as_float(value) -> float:
    """A row's value as a float; NaN for ``None``, ``""`` or text that is not a number.

    >>> as_float("0.5"), as_float(None), as_float("")
    (0.5, nan, nan)
    """
    try:
        return float("nan") if value is None or value == "" else float(value)
    except (TypeError, ValueError):
        return float("nan")


def in_order(rows: Iterable[dict]) -> list[dict]:
    """Rows sorted by detector, task, seed and cell (a fixed order for sums)."""
    return sorted(rows, key=lambda r: (str(r["detector"]), str(r["task"]), r["seed"], r["cell_id"]))


def mean(values: Iterable[float]) -> float:
    """The mean of the values that are not NaN (NaN if none)."""
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    return float(arr.mean()) if arr.size else float("nan")


def sd(values: Sequence[float]) -> float:
    """The sample standard deviation (``ddof=1``) of the values that are not NaN (NaN for fewer than 2)."""
    arr = np.array([v for v in values if not math.isnan(v)], dtype=float)
    return float(arr.std(ddof=1)) if arr.size > 1 else float("nan")
