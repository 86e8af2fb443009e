"""Novelty labels: 0 normal, 1 novel, and nothing else.

A label that is neither is refused rather than read one way or another,
since each reading silently changes the experiment: ``NaN`` would count as
novel under ``y != 0``, scikit-learn's ``-1`` (outlier) / ``+1`` (inlier)
would make every scan novel, ``0.5`` would be none under ``int(y)``. The
conversion from scikit-learn's convention is named in the message:
``y = (y == -1).astype(int)``.

A test part needs both classes: with no novel scan (or no normal one) ROC
AUC and average precision are undefined, and a run would report nothing
measured as if it were a result.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["check_labels", "check_both_classes", "SKLEARN_CONVERSION"]

#: how to turn scikit-learn's outlier labels (-1 outlier, +1 inlier) into novelty labels
SKLEARN_CONVERSION = "y = (y == -1).astype(int)"


def _at(where: Callable[[int], str] | str, i: int) -> str:
    return where(i) if callable(where) else f"{where}, row {i}"


def check_labels(y, where: Callable[[int], str] | str = "labels") -> np.ndarray:
    """``y`` as int64 0/1 labels; anything else refused, naming the first bad label and where it is.

    ``where`` is a text (``"task 'lab', labels"``: the row is appended) or
    a function of the row index giving its place (a file's line).

    >>> check_labels([0, 1, 1.0, True]).tolist()
    [0, 1, 1, 1]
    >>> check_labels([1, -1, 1])
    Traceback (most recent call last):
    ...
    ValueError: labels, row 1: the labels are -1 and +1, scikit-learn's outlier convention (-1 outlier, +1 inlier); novelty labels are 0 (normal) and 1 (novel): convert with y = (y == -1).astype(int).
    """
    values = np.asarray(y)
    if values.ndim != 1:
        values = values.reshape(-1) if values.ndim == 2 and 1 in values.shape else values
    if values.ndim != 1:
        raise ValueError(f"{where if isinstance(where, str) else 'labels'}: expected one label a scan; "
                         f"got shape {np.shape(y)}.")
    if values.dtype.kind not in "biuf":
        bad = next((i for i, v in enumerate(values) if not _is_number(v)), 0)
        raise ValueError(f"{_at(where, bad)}: expected a label 0 (normal) or 1 (novel), got {str(values[bad])!r}.")
    values = values.astype(np.float64)
    nan = np.flatnonzero(np.isnan(values))
    if nan.size:
        raise ValueError(f"{_at(where, int(nan[0]))}: the label is NaN; every scan needs a label, 0 (normal) "
                         "or 1 (novel).")
    wrong = np.flatnonzero((values != 0) & (values != 1))
    if wrong.size:
        i = int(wrong[0])
        if set(np.unique(values).tolist()) <= {-1.0, 1.0}:
            raise ValueError(f"{_at(where, i)}: the labels are -1 and +1, scikit-learn's outlier convention "
                             "(-1 outlier, +1 inlier); novelty labels are 0 (normal) and 1 (novel): convert "
                             f"with {SKLEARN_CONVERSION}.")
        raise ValueError(f"{_at(where, i)}: expected a label 0 (normal) or 1 (novel), got {values[i]:g}.")
    return values.astype(np.int64)


def check_both_classes(y, what: str) -> None:
    """Refuse test labels without a novel or without a normal scan (ROC AUC needs both), saying why.

    >>> check_both_classes([0, 0, 0], "task 'lab'")
    Traceback (most recent call last):
    ...
    ValueError: task 'lab': the test part has no novel scan (3 scans, all labelled 0); ROC AUC and average precision need novel and normal test scans.
    """
    y = np.asarray(y)
    n_novel = int(np.count_nonzero(y))
    if n_novel == 0 or n_novel == y.size:
        missing, label = ("novel", 0) if n_novel == 0 else ("normal", 1)
        raise ValueError(f"{what}: the test part has no {missing} scan ({y.size} scans, all labelled {label}); "
                         "ROC AUC and average precision need novel and normal test scans.")


def _is_number(value) -> bool:
    try:
        float(value)
    except (TypeError, ValueError):
        return False
    return True
