"""Timestamps of scans: the elapsed time before each, and the times of a repeated pass."""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

from .scans import _refuse_not_real

__all__ = ["check_timestamps", "last_timestamp", "pass_timestamps"]

_INT64_MAX = np.iinfo(np.int64).max


def _not_numeric(exc: Exception) -> ValueError:
    return ValueError(f"timestamps must be numbers; got values that are not numeric ({exc}).")


def check_timestamps(timestamps: Any, n_samples: int, last_time: float | int | None) -> np.ndarray:
    """Validate timestamps and return the elapsed time before each scan.

    The first scan of a model's life has dt = 1 (one step), as without
    timestamps; afterwards dt is the time since the previous scan. Integer
    timestamps (epoch nanoseconds) are subtracted as integers, exactly, and
    only their differences become floats: a float64 holds 1.7e18 only to
    the nearest 256, so ``t - 1`` or ``t + 100`` would be lost.
    """
    try:
        t = np.asarray(timestamps)
    except (TypeError, ValueError) as exc:  # ragged
        raise _not_numeric(exc) from None
    _refuse_not_real(t.dtype.kind, "timestamps must be real numbers")
    exact = t.dtype.kind in "iu" and t.dtype.itemsize <= 8 and not (t.dtype.kind == "u" and t.size
                                                                    and t.max() > _INT64_MAX)
    try:
        t = t.astype(np.int64 if exact else np.float64, copy=False)
    except (TypeError, ValueError) as exc:
        raise _not_numeric(exc) from None
    if t.ndim != 1 or t.shape[0] != n_samples:
        raise ValueError(
            f"timestamps must be a 1-D array with one value per scan ({n_samples}); "
            f"got shape {t.shape}."
        )
    if not exact and not np.all(np.isfinite(t)):
        raise ValueError("timestamps contain NaN or infinity.")
    if np.any(t[1:] < t[:-1]) or (n_samples and last_time is not None and _elapsed(t[0], last_time) < 0):
        raise ValueError("timestamps must not decrease (each scan is at or after the previous one).")
    dt = np.empty(n_samples)
    if n_samples:
        dt[0] = 1.0 if last_time is None else _elapsed(t[0], last_time)
    if exact:
        # non-decreasing int64: the difference modulo 2**64 is the exact difference
        dt[1:] = (t[1:].view(np.uint64) - t[:-1].view(np.uint64)).astype(np.float64)
    else:
        with np.errstate(over="ignore"):  # an infinite gap is refused below
            dt[1:] = np.diff(t)
    if not np.all(np.isfinite(dt)):  # two finite times more than 1.8e308 apart
        raise ValueError("the time between two scans must be finite (below 1.8e308).")
    return dt


def last_timestamp(timestamps: Any) -> float | int:
    """The last of validated ``timestamps``, as it was given: an int stays an exact int."""
    t = np.asarray(timestamps)
    last = t.reshape(-1)[-1]
    if t.dtype.kind in "iu" and t.dtype.itemsize <= 8 and int(last) <= _INT64_MAX:
        return int(last)
    return float(last)


def _elapsed(t: Any, last_time: float | int) -> float:
    """``t - last_time``, exact when both are integers."""
    if isinstance(t, np.integer) and isinstance(last_time, numbers.Integral):
        return float(int(t) - int(last_time))
    return float(t) - float(last_time)


def pass_timestamps(t, k: int) -> np.ndarray:
    """The timestamps of the ``k``-th pass over a route first driven at times ``t``."""
    t = np.asarray(t, dtype=np.float64)
    steps = np.diff(t)
    step = float(np.median(steps[steps > 0])) if np.any(steps > 0) else 1.0
    return t + k * (t[-1] - t[0] + step)
