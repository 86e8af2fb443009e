"""Feature names: a dict scan's keys, a data frame's columns, checked against those learned.

scikit-learn's rules for ``feature_names_in_`` and its wording for names
unseen, missing or out of order.
"""

from __future__ import annotations

import numbers
import warnings
from typing import Any

import numpy as np

__all__ = ["scan_names", "frame_names", "check_feature_names"]


def _type_name(value: Any) -> str:
    return type(value).__name__



def scan_names(x: dict, owner: Any) -> np.ndarray:
    """The feature names of a dict scan: its keys, sorted.

    Keys must be all strings (returned as an object array, as scikit-learn's
    ``feature_names_in_``) or all integers (an int64 array, e.g. River's
    ``iter_array`` positions), so that any key order gives the same features.
    """
    keys = list(x)
    if all(isinstance(k, str) for k in keys):
        return np.array(sorted(keys), dtype=object)
    if all(isinstance(k, numbers.Integral) and not isinstance(k, bool) for k in keys):
        return np.array(sorted(keys), dtype=np.int64)
    kinds = sorted({_type_name(k) for k in keys})
    raise ValueError(
        f"{_type_name(owner)} reads a dict scan by its keys, which must be all strings or all "
        f"integers (feature names); got keys of types {', '.join(kinds)}."
    )


def _dict_values(x: dict, owner: Any, n_features: int | None, names: np.ndarray | None) -> list:
    if names is None:
        if n_features is not None:
            raise ValueError(
                f"{_type_name(owner)} learned from arrays without feature names, so it cannot tell "
                f"which of its {n_features} features a dict key is. Give the scan as an array in "
                "the order learned, or learn from dict scans (or a DataFrame) from the start."
            )
        names = scan_names(x, owner)
    keys = names.tolist()
    try:
        values = [x[k] for k in keys]
    except KeyError:
        values = None
    if values is None or len(x) != len(keys):
        raise ValueError(
            f"The keys of x do not match the features {_type_name(owner)} learned.\n"
            + _name_mismatch(keys, list(x))
        )
    return values


def _name_mismatch(learned: list, given: list) -> str:
    """Which names are unexpected or missing (scikit-learn's wording), or that the order differs."""
    learned_set, given_set = set(learned), set(given)
    unexpected = sorted((n for n in given_set - learned_set), key=str)
    missing = sorted((n for n in learned_set - given_set), key=str)
    text = ""
    for title, names in (("Feature names unseen at fit time:", unexpected),
                         ("Feature names seen at fit time, yet now missing:", missing)):
        if names:
            shown = [f"- {n!r}" if not isinstance(n, str) else f"- {n}" for n in names[:5]]
            text += title + "\n" + "\n".join(shown + (["- ..."] if len(names) > 5 else [])) + "\n"
    return text or "Feature names must be in the same order as they were in fit.\n"


def frame_names(X: Any) -> np.ndarray | None:
    """The column names of a DataFrame (or any table with ``columns``) if all are strings.

    scikit-learn's rule for ``feature_names_in_``; pandas is not needed.
    """
    columns = getattr(X, "columns", None)
    if columns is None:
        return None
    names = list(columns)
    if names and all(isinstance(c, str) for c in names):
        return np.array(names, dtype=object)
    return None


def check_feature_names(owner: Any, names: np.ndarray | None, learned: np.ndarray | None) -> None:
    """Refuse a batch whose column names differ from the feature names learned.

    As scikit-learn: different names, or the same in another order, are an
    error; names on one side only, a warning.
    """
    if names is None and learned is None:
        return
    if names is None or learned is None:
        side = ("X does not have valid feature names, but {} was fitted with feature names"
                if names is None else "X has feature names, but {} was fitted without feature names")
        warnings.warn(side.format(_type_name(owner)), UserWarning, stacklevel=3)
        return
    if len(names) != len(learned) or names.tolist() != learned.tolist():
        raise ValueError(
            "The feature names should match those that were passed during fit.\n"
            + _name_mismatch(learned.tolist(), names.tolist())
        )
