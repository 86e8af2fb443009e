"""Checks of parameters and inputs, with one message form for the whole project.

Parameter messages follow scikit-learn's form::

    The 'max_age' parameter of GrowingNeuralGas must be an int in [1, inf). Got 0 instead.

Input checks translate to ``ValueError`` (or ``TypeError`` for sparse input,
as scikit-learn does) *before* any state changes, so a rejected call leaves a
model exactly as it was.

Scans are finite real numbers whose Euclidean norm is at most
:data:`MAX_SCAN_NORM` (1e100). The detectors' distances are squared: two
scans of norm up to 1e154 already give a squared distance that overflows to
infinity and turns the learned state into NaN. With the bound, a squared
distance between scans or prototypes (convex combinations of scans) is at
most 4e200, which leaves room for sums of many of them (a network's
accumulated errors, a mixture's covariances) below the float64 limit of
1.8e308. Complex numbers and dates are refused rather than converted.
"""

from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "Interval",
    "Options",
    "Instance",
    "Bounds",
    "validate_parameters",
    "check_batch",
    "check_one",
    "check_timestamps",
    "pass_timestamps",
    "scan_names",
    "frame_names",
    "check_feature_names",
    "MAX_SCAN_NORM",
]

#: the largest Euclidean norm of a scan any detector accepts (see the module docstring)
MAX_SCAN_NORM = 1e100
_MAX_SQUARED_NORM = MAX_SCAN_NORM**2

# dtype kinds that numpy would convert to float64 by dropping information:
# complex (the imaginary part) and datetime / timedelta (the unit)
_NOT_REAL = {"c": "complex numbers", "M": "dates (datetime64)", "m": "time spans (timedelta64)"}


def _type_name(value: Any) -> str:
    return type(value).__name__


@dataclass(frozen=True)
class Interval:
    """A real or integer range; ``None`` bounds are infinite."""

    kind: type  # numbers.Integral or numbers.Real
    low: float | None = None
    high: float | None = None
    closed: str = "both"  # "both", "left", "right", "neither"
    allow_none: bool = False

    def accepts(self, value: Any) -> bool:
        if value is None:
            return self.allow_none
        if isinstance(value, bool) or not isinstance(value, self.kind):
            return False
        if isinstance(value, numbers.Real) and not math.isfinite(value) and value == value:
            # +-inf is only acceptable as an unbounded side, never as a value
            return False
        if value != value:  # NaN
            return False
        left_ok = self.low is None or (value >= self.low if self.closed in ("both", "left") else value > self.low)
        right_ok = self.high is None or (value <= self.high if self.closed in ("both", "right") else value < self.high)
        return left_ok and right_ok

    def describe(self) -> str:
        what = "an int" if self.kind is numbers.Integral else "a float"
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        lb = "[" if self.closed in ("both", "left") and self.low is not None else "("
        rb = "]" if self.closed in ("both", "right") and self.high is not None else ")"
        text = f"{what} in {lb}{lo}, {hi}{rb}"
        return text + (" or None" if self.allow_none else "")


@dataclass(frozen=True)
class Options:
    """One of a fixed set of values."""

    values: tuple

    def accepts(self, value: Any) -> bool:
        return isinstance(value, (str, bool, numbers.Number, type(None))) and value in self.values

    def describe(self) -> str:
        return "one of " + ", ".join(repr(v) for v in self.values)


@dataclass(frozen=True)
class Instance:
    """An instance of one of the given types (strings name registry entries)."""

    types: tuple
    description: str

    def accepts(self, value: Any) -> bool:
        return isinstance(value, self.types)

    def describe(self) -> str:
        return self.description


@dataclass(frozen=True)
class Bounds:
    """A pair ``(low, high)`` of finite real numbers (booleans are not numbers here), ``low < high``."""

    def accepts(self, value: Any) -> bool:
        finite = Interval(numbers.Real)
        return (isinstance(value, (tuple, list)) and len(value) == 2
                and all(finite.accepts(v) for v in value) and bool(value[0] < value[1]))

    def describe(self) -> str:
        return "a pair (low, high) of finite floats with low < high"


def validate_parameters(owner: Any, rules: dict | None = None) -> None:
    """Check every parameter of ``owner`` against ``rules`` (default: ``owner._parameter_rules``).

    Each rule is an :class:`Interval`, :class:`Options`, :class:`Instance`,
    :class:`Bounds` or a tuple of them (any may accept).
    """
    if rules is None:
        rules = getattr(owner, "_parameter_rules", {})
    for name, rule in rules.items():
        value = getattr(owner, name)
        alternatives = rule if isinstance(rule, tuple) else (rule,)
        if not any(alt.accepts(value) for alt in alternatives):
            expected = " or ".join(alt.describe() for alt in alternatives)
            raise ValueError(
                f"The '{name}' parameter of {type(owner).__name__} must be {expected}. "
                f"Got {value!r} instead."
            )


# --------------------------------------------------------------------- inputs
def check_batch(X: Any, owner: Any, n_features: int | None = None) -> np.ndarray:
    """Validate a batch of scans: a finite, numeric, non-empty 2-D array.

    Returns a C-contiguous float64 array (a copy only when needed; the caller's
    array is never written to).
    """
    from sklearn.utils import check_array  # deferred: keeps ``import novelty`` light

    _refuse_not_real(_dtype_kinds(X), f"{type(owner).__name__} expects X as real numbers")
    try:
        X = check_array(X, dtype=np.float64, order="C", estimator=owner, input_name="X",
                        ensure_all_finite=False)
    except (TypeError, ValueError) as exc:
        # numpy's own conversion errors name neither the model nor what it expects
        if not str(exc).startswith(("could not convert", "setting an array element", "float() argument")):
            raise
        # the same type as numpy's (scikit-learn's checks expect a TypeError for objects)
        raise type(exc)(
            f"{type(owner).__name__} expects X as a 2-D array of numbers of shape "
            f"(n_samples, n_features); got values that are not numeric ({exc})."
        ) from None
    # One pass gives every row's squared norm; NaN, infinity and too large
    # values all fail the comparison.
    squared = np.einsum("ij,ij->i", X, X)
    if X.shape[0] and not squared.max() <= _MAX_SQUARED_NORM:
        if not np.all(np.isfinite(X)):
            bad = int(np.flatnonzero(~np.isfinite(X).all(axis=1))[0])
            raise ValueError(
                f"Input X contains NaN or infinity (first in row {bad}); "
                f"{type(owner).__name__} expects finite numbers."
            )
        bad = int(np.flatnonzero(~(squared <= _MAX_SQUARED_NORM))[0])
        raise ValueError(_too_large("X", owner, f" (first in row {bad})"))
    if n_features is not None and X.shape[1] != n_features:
        raise ValueError(
            f"X has {X.shape[1]} features, but {type(owner).__name__} is expecting "
            f"{n_features} features as input."
        )
    return X


def check_one(x: Any, owner: Any, n_features: int | None, names: np.ndarray | None = None) -> np.ndarray:
    """Validate one scan cheaply (the robot's hot path): a finite 1-D vector.

    A dict scan is read by key: in the order of ``names`` (the feature names
    the model learned), or, before anything is learned, of its sorted keys.
    """
    if type(x) is np.ndarray and x.dtype == np.float64 and x.ndim == 1:
        arr = x
    else:
        if isinstance(x, dict):
            x = _dict_values(x, owner, n_features, names)
        try:
            arr = np.asarray(x)
            _refuse_not_real(arr.dtype.kind, f"{type(owner).__name__} expects one scan as real numbers")
            arr = arr.astype(np.float64, copy=False)
        except (TypeError, ValueError) as exc:
            if isinstance(exc, _NotReal):
                raise

            raise ValueError(
                f"{type(owner).__name__} expects one scan as a 1-D sequence of numbers; "
                f"got values that are not numeric ({exc})."
            ) from None
        if arr.ndim != 1:
            raise ValueError(
                f"{type(owner).__name__} expects one scan as a 1-D array of shape "
                f"(n_features,); got an array of shape {arr.shape}. "
                "Use the batch methods for 2-D input."
            )
    if arr.shape[0] == 0:
        raise ValueError(f"{type(owner).__name__} got an empty scan; expected at least one feature.")
    if n_features is not None and arr.shape[0] != n_features:
        raise ValueError(
            f"x has {arr.shape[0]} features, but {type(owner).__name__} is expecting "
            f"{n_features} features as input."
        )
    # One reduction (the squared norm: NaN, infinity and too large values all fail
    # the comparison); the elementwise mask only to say which.
    if not np.dot(arr, arr) <= _MAX_SQUARED_NORM:
        if not np.isfinite(arr).all():
            raise ValueError(f"Input x for {type(owner).__name__} contains NaN or infinity.")
        raise ValueError(_too_large("x", owner, ""))
    return arr


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


class _NotReal(ValueError):
    """Input of a kind that converting to float64 would silently damage."""


def _dtype_kinds(X: Any) -> str:
    """The numpy dtype kinds of ``X`` (its columns' for a data frame) without converting it."""
    dtypes = getattr(X, "dtypes", None)
    if dtypes is not None and not isinstance(X, np.ndarray):
        return "".join(getattr(d, "kind", "O") for d in np.atleast_1d(dtypes))
    dtype = getattr(X, "dtype", None)
    if dtype is None and isinstance(X, (list, tuple)):
        try:
            dtype = np.asarray(X).dtype
        except (TypeError, ValueError):  # ragged: check_array says so
            return ""
    return getattr(dtype, "kind", "")


def _refuse_not_real(kinds: str, expected: str) -> None:
    for kind, what in _NOT_REAL.items():
        if kind in kinds:
            # scikit-learn's wording for complex input, which its estimator checks look for
            prefix = "Complex data not supported: " if kind == "c" else ""
            raise _NotReal(f"{prefix}{expected}; got {what}. Convert them to real numbers first.")


def _too_large(name: str, owner: Any, where: str) -> str:
    return (
        f"Input {name} for {type(owner).__name__} has a scan of Euclidean norm above "
        f"{MAX_SCAN_NORM:g}{where}, the largest the detectors accept (their squared "
        "distances would overflow); rescale the data."
    )


def check_timestamps(timestamps: Any, n_samples: int, last_time: float | None) -> np.ndarray:
    """Validate timestamps and return the elapsed time before each scan.

    The first scan of a model's life has dt = 1 (one step), as without
    timestamps; afterwards dt is the time since the previous scan.
    """
    try:
        t = np.asarray(timestamps)
        _refuse_not_real(t.dtype.kind, "timestamps must be real numbers")
        t = t.astype(np.float64, copy=False)
    except (TypeError, ValueError) as exc:
        if isinstance(exc, _NotReal):
            raise
        raise ValueError(f"timestamps must be numbers; got values that are not numeric ({exc}).") from None
    if t.ndim != 1 or t.shape[0] != n_samples:
        raise ValueError(
            f"timestamps must be a 1-D array with one value per scan ({n_samples}); "
            f"got shape {t.shape}."
        )
    if not np.all(np.isfinite(t)):
        raise ValueError("timestamps contain NaN or infinity.")
    previous = t[0] - 1.0 if last_time is None else last_time
    dt = np.diff(t, prepend=previous)
    if np.any(dt < 0):
        raise ValueError("timestamps must not decrease (each scan is at or after the previous one).")
    if not np.all(np.isfinite(dt)):  # two finite times more than 1.8e308 apart
        raise ValueError("the time between two scans must be finite (below 1.8e308).")
    return dt


def pass_timestamps(t, k: int) -> np.ndarray:
    """The timestamps of the ``k``-th pass over a route first driven at times ``t``."""
    t = np.asarray(t, dtype=np.float64)
    steps = np.diff(t)
    step = float(np.median(steps[steps > 0])) if np.any(steps > 0) else 1.0
    return t + k * (t[-1] - t[0] + step)
