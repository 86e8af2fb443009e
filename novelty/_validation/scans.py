"""Checks of scans: a batch, or one scan, of finite real numbers within the norm bound.

Scans are finite real numbers whose Euclidean norm is at most
:data:`MAX_SCAN_NORM` (1e100). The detectors' distances are squared: two
scans of norm up to 1e154 already give a squared distance that overflows to
infinity and turns the learned state into NaN. With the bound, a squared
distance between scans or prototypes (convex combinations of scans) is at
most 4e200, which leaves room for sums of many of them (a network's
accumulated errors, a mixture's covariances) below the float64 limit of
1.8e308. Complex numbers and dates are refused rather than converted, and so
is text: numpy would read the string ``"0.3"`` as 0.3, but a string among
scans is usually a cell a reader left unconverted (``"n/a"`` next to
``"0.3"``), which only reading every string as a number would hide.

Shares its name with ``novelty/io/scans/``: the scans a detector is given, checked, and a
recording's messages made scans.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .names import _dict_values

__all__ = ["check_batch", "check_one", "MAX_SCAN_NORM"]

#: the largest Euclidean norm of a scan any detector accepts (see the module docstring)
MAX_SCAN_NORM = 1e100
_MAX_SQUARED_NORM = MAX_SCAN_NORM**2
#: a batch (or scan) whose squared values sum to at most this, in any order, has every row
#: within the bound: the margin is far wider than the rounding of any such sum
CLEARED = _MAX_SQUARED_NORM * (1 - 1e-6)
# arrays taken as they are (float32 converted): the dtypes of the common input
_PLAIN_FLOATS = (np.dtype(np.float64), np.dtype(np.float32))

# dtype kinds that numpy would convert to float64 by dropping information:
# complex (the imaginary part) and datetime / timedelta (the unit)
_NOT_REAL = {"c": "complex numbers", "M": "dates (datetime64)", "m": "time spans (timedelta64)"}


def check_batch(X: Any, owner: Any, n_features: int | None = None) -> np.ndarray:
    """Validate a batch of scans: a finite, numeric, non-empty 2-D array.

    Returns a C-contiguous float64 array (a copy only when needed; the caller's
    array is never written to).
    """
    if (type(X) is np.ndarray and X.ndim == 2 and X.dtype in _PLAIN_FLOATS
            and X.shape[0] and X.shape[1]):
        # The common input, a plain non-empty 2-D float array: what scikit-learn's
        # check_array would return, without its general machinery (data frame
        # probing: most of a short batch's cost). Anything else takes that way.
        if X.dtype != np.float64 or not X.flags.c_contiguous:
            X = np.ascontiguousarray(X, dtype=np.float64)
    else:
        X = _converted(X, owner)
    _check_norms(X, owner)
    if n_features is not None and X.shape[1] != n_features:
        raise ValueError(
            f"X has {X.shape[1]} features, but {type(owner).__name__} is expecting "
            f"{n_features} features as input."
        )
    return X


def _converted(X: Any, owner: Any) -> np.ndarray:
    """``X`` as a C-contiguous float64 2-D array by scikit-learn's ``check_array`` (its checks
    of shape, emptiness and sparsity, and its messages), numbers only."""
    from sklearn.utils import check_array  # deferred: keeps ``import novelty`` light

    kinds = _dtype_kinds(X)
    _refuse_not_real(kinds, f"{type(owner).__name__} expects X as real numbers")
    if set(kinds) & set(_MAY_HOLD_TEXT):
        _refuse_text_cells(X, owner)
    try:
        return check_array(X, dtype=np.float64, order="C", estimator=owner, input_name="X",
                           ensure_all_finite=False)
    except OverflowError:  # a Python int beyond float64
        raise _beyond_float(owner, "X") from None
    except (TypeError, ValueError) as exc:
        # numpy's own conversion errors name neither the model nor what it expects
        if not str(exc).startswith(("could not convert", "setting an array element", "float() argument")):
            raise
        # the same type as numpy's (scikit-learn's checks expect a TypeError for objects)
        raise type(exc)(
            f"{type(owner).__name__} expects X as a 2-D array of numbers of shape "
            f"(n_samples, n_features); got values that are not numeric ({exc})."
        ) from None


def _check_norms(X: np.ndarray, owner: Any) -> None:
    """Refuse a row that is not finite or whose norm is above the bound (the first such row named).

    The sum of every squared value bounds each row's squared norm from above
    (sums of non-negative numbers only grow, rounded or not), so one dot
    product clears a batch well inside the bound (a margin of 1e-6 covers the
    rounding of either sum); NaN, infinity and too large values all fail the
    comparison, and then the rows are checked one by one.
    """
    if cleared(X):
        return
    # Scans of accepted norms can overflow the rows' sums (and a refused value): that
    # overflow is an answer here, not something to warn a user about. One pass gives every
    # row's squared norm.
    with np.errstate(over="ignore", invalid="ignore"):
        squared = np.einsum("ij,ij->i", X, X)
    if not squared.max() <= _MAX_SQUARED_NORM:
        if not np.all(np.isfinite(X)):
            bad = int(np.flatnonzero(~np.isfinite(X).all(axis=1))[0])
            raise ValueError(
                f"Input X contains NaN or infinity (first in row {bad}); "
                f"{type(owner).__name__} expects finite numbers."
            )
        bad = int(np.flatnonzero(~(squared <= _MAX_SQUARED_NORM))[0])
        raise ValueError(_too_large("X", owner, f" (first in row {bad})"))


def cleared(a: np.ndarray) -> bool:
    """Whether the sum of the squares of ``a`` is within ``CLEARED``: then every value is finite
    and every row's norm within the bound (as :func:`_check_norms` clears a batch); NaN,
    infinity and too large values fail. Overflow is an answer here, never a warning: a short
    contiguous float64 array (1 to 4096 values) by BLAS's ``ddot`` as scipy gives it, which
    sets no numpy error state (numpy's ``dot`` warns on overflow, and its ``errstate``
    context cost more than the sum itself in a call that scores one scan); else
    under ``np.errstate``, by einsum's loop over a strided matrix (the compiled engine's
    ``weights_``, a transposed view, is not copied) or over the values (a long array: BLAS
    may split it over threads, whose wake-up was seen to cost milliseconds on a busy
    machine). Only a float array is cleared (integer squares wrap around): any other answers
    False."""
    if a.dtype.kind != "f":
        return False
    if a.dtype == np.float64 and 0 < a.size <= 4096 and a.flags.c_contiguous:
        flat = a.reshape(-1)
        return _ddot()(flat, flat) <= CLEARED
    # summed in float64 at least: a float32 array's squares overflow float32 from about 1.8e19,
    # far inside the bound
    wide = np.result_type(a.dtype, np.float64)
    with np.errstate(over="ignore", invalid="ignore"):
        if a.ndim == 2 and not a.flags.c_contiguous:
            total = np.einsum("ij,ij->", a, a, dtype=wide)
        else:
            flat = a.reshape(-1)  # a view where the memory is contiguous
            total = np.einsum("i,i->", flat, flat, dtype=wide)
    # compared as a Python float: a float32 sum against CLEARED would turn CLEARED into
    # float32's infinity (NEP 50), and clear an array holding infinity
    return float(total) <= CLEARED


def _ddot():
    """scipy's BLAS ``ddot``, imported at its first use (scipy.linalg is slow to import,
    docs/guide/performance.md; fitting a model imports it anyway, through scikit-learn)."""
    global _DDOT
    if _DDOT is None:
        from scipy.linalg.blas import ddot

        _DDOT = ddot
    return _DDOT


_DDOT = None


def check_one(x: Any, owner: Any, n_features: int | None, names: np.ndarray | None = None) -> np.ndarray:
    """Validate one scan cheaply (the robot's hot path): a finite 1-D vector.

    A dict scan is read by key: in the order of ``names`` (the feature names
    the model learned), or, before anything is learned, of its sorted keys.
    """
    if type(x) is np.ndarray and x.dtype == np.float64 and x.ndim == 1:
        arr = x
    else:
        if isinstance(x, dict):
            key = next((k for k, v in x.items() if isinstance(v, _TEXT)), None)
            if key is not None:
                raise ValueError(_text_in_scan(owner, x[key], f"the value of key {key!r}"))
            x = _dict_values(x, owner, n_features, names)
        try:
            arr = np.asarray(x)
        except (TypeError, ValueError) as exc:  # ragged
            raise _not_numeric(owner, exc) from None
        # refused by what they hold, before a conversion to float64 would damage them silently
        if arr.dtype.kind in _MAY_HOLD_TEXT:
            _refuse_text_values(x, arr, owner)
        _refuse_not_real(arr.dtype.kind, f"{type(owner).__name__} expects one scan as real numbers")
        try:
            arr = arr.astype(np.float64, copy=False)
        except OverflowError:  # a Python int beyond float64
            raise _beyond_float(owner, "the scan") from None
        except (TypeError, ValueError) as exc:
            raise _not_numeric(owner, exc) from None
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
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is a refusal, said below
        squared = np.dot(arr, arr)
    if not squared <= _MAX_SQUARED_NORM:
        if not np.isfinite(arr).all():
            raise ValueError(f"Input x for {type(owner).__name__} contains NaN or infinity.")
        raise ValueError(_too_large("x", owner, ""))
    return arr


# what a string is, and the dtype kinds an array of them (or holding them) has
_TEXT = (str, bytes)
_MAY_HOLD_TEXT = "USO"


def _not_numeric(owner: Any, exc: Exception) -> ValueError:
    return ValueError(f"{type(owner).__name__} expects one scan as a 1-D sequence of numbers; "
                      f"got values that are not numeric ({exc}).")


def _text_in_scan(owner: Any, value: Any, where: str) -> str:
    return (f"{type(owner).__name__} expects one scan of numbers; got the string {value!r} as {where}; "
            "convert text to numbers first.")


def _refuse_text_values(x: Any, arr: np.ndarray, owner: Any) -> None:
    """Refuse a scan holding a string (its first one named by position)."""
    values = x if isinstance(x, (list, tuple)) else arr.reshape(-1).tolist()
    i = next((i for i, v in enumerate(values) if isinstance(v, _TEXT)), None)
    if i is not None:
        raise ValueError(_text_in_scan(owner, values[i], f"value {i}"))


def _refuse_text_cells(X: Any, owner: Any) -> None:
    """Refuse a batch holding a string (its first one named by row and column)."""
    try:
        cells = np.asarray(X, dtype=object)
    except (TypeError, ValueError):  # ragged: check_array says so
        return
    if cells.ndim != 2:
        return
    is_text = np.frompyfunc(lambda v: isinstance(v, _TEXT), 1, 1)(cells).astype(bool)
    if is_text.any():
        i, j = np.argwhere(is_text)[0]
        raise ValueError(
            f"{type(owner).__name__} expects X as a 2-D array of numbers; got the string "
            f"{cells[i, j]!r} in row {i}, column {j}; convert text to numbers first.")


def _beyond_float(owner: Any, what: str) -> ValueError:
    return ValueError(
        f"{type(owner).__name__}: {what} holds an integer beyond the float64 range (about 1.8e308); "
        f"scans are vectors of finite numbers of norm at most {MAX_SCAN_NORM:g}."
    )


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
            raise ValueError(f"{prefix}{expected}; got {what}. Convert them to real numbers first.")


def _too_large(name: str, owner: Any, where: str) -> str:
    return (
        f"Input {name} for {type(owner).__name__} has a scan of Euclidean norm above "
        f"{MAX_SCAN_NORM:g}{where}, the largest the detectors accept (their squared "
        "distances would overflow); rescale the data."
    )
