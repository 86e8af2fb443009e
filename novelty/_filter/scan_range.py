"""A warning, once per detector, of scans far outside the range its clusterer assumes.

The paper's detector on standardised scans (StandardScaler) learns little and
flags nothing, silently: its units start uniformly in [0, 1], the range of the
paper's preprocessed sonar readings, far from every scan. This says why.
"""

from __future__ import annotations

import warnings
import weakref

import numpy as np

__all__ = ["ScanRangeWarning", "warn_once", "carry"]

#: the detectors already warned of their scans' range: once per detector object, kept out of
#: its state (a model file, a copy and a comparison of states do not see it)
_WARNED: "weakref.WeakSet" = weakref.WeakSet()


class ScanRangeWarning(UserWarning):
    """Scans far outside the range a detector's parameters assume.

    The range is the clusterer's
    :meth:`~novelty.clusterers.base.Clusterer.assumed_range`; silence it with
    ``warnings.filterwarnings("ignore", category=novelty.ScanRangeWarning)``.
    """


def warn_once(detector, X: np.ndarray) -> None:
    """Warn, once per ``detector``, if ``X`` lies far outside the range its fitted clusterer
    assumes: beyond it by more than its width ([-1, 2] for [0, 1])."""
    if detector in _WARNED:
        return
    assumed = detector.clusterer_.assumed_range()
    if assumed is None:
        return
    low, high = assumed
    width = high - low
    least, most = float(X.min()), float(X.max())
    if least >= low - width and most <= high + width:
        return
    _WARNED.add(detector)
    warnings.warn(
        f"{type(detector).__name__}: its clusterer {type(detector.clusterer_).__name__} starts its units "
        f"uniformly in [{low:g}, {high:g}] (init='uniform'), the range its parameters assume (the paper's "
        f"preprocessed sonar readings); these scans lie far outside it (from {least:.3g} to {most:.3g}). "
        f"Scale them into [{low:g}, {high:g}] (MinMaxScaler; preprocess='paper' for ranges in metres), "
        "or set init_range to their range, or init='sample'.", ScanRangeWarning, stacklevel=3)


def carry(detector, fitted) -> None:
    """``detector`` adopts the model ``fitted`` learned in a copy: warned if the copy was."""
    if fitted in _WARNED:
        _WARNED.add(detector)
