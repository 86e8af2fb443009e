"""Timestamps of scans: the elapsed time before each, and the times of a repeated pass."""

from __future__ import annotations

from typing import Any

import numpy as np

from .scans import _NotReal, _refuse_not_real

__all__ = ["check_timestamps", "pass_timestamps"]


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
