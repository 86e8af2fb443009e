"""Learning while the match scale is calibrated: each scan scored with the scale of those before it.

A filter whose novelty rule (or clusterer) needs the match scale sigma and
was not given one calibrates it on the first ``calibration_scans`` scans it
learns (:class:`novelty.match_scale.ScaleCalibration`), one scan at a time, so
that the numbers do not depend on how the scans were batched: each scan is
scored with the scale of the scans before it (none before two distinct scans:
the efficacy alone), then added to the calibration. A clusterer that learns
by the scale (``Clusterer.uses_match_scale``: GWR's ``"auto"`` radius) learns
one scan at a time meanwhile, given each new scale; any other learns the
batch in one call, since its learning does not read the scale. The learning,
and the scale given to the clusterer, are the engine's
(:meth:`~novelty._kernels.reference.ReferenceEngine.learn_calibrating`); the
novelty of each scan, combined with its own scale, is the filter's.
"""

from __future__ import annotations

import numpy as np

from ..match_scale import mismatch_novelty, product_novelty

__all__ = ["learn_calibrating"]


def learn_calibrating(detector, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
    """The novelty of the rows of ``X``, learned by ``detector`` while (and after) its
    calibration (``detector._calibration``, not full) takes them: its engine learns them
    (:meth:`~novelty._kernels.reference.ReferenceEngine.learn_calibrating`), and each
    calibrating row's novelty is combined with the scale of the rows before it."""
    calibration = detector._calibration
    n = X.shape[0]
    distances = None if detector.novelty_rule == "efficacy" else np.empty(n)
    efficacy, scales, scale = detector._current_engine().learn_calibrating(
        X, dt, float(detector.stimulus), calibration, detector.match_scale_, distances)
    if scale is not detector.match_scale_:
        detector.match_scale_ = scale
    detector.calibration_scans_ = calibration.scans
    k, m = len(scales), efficacy.shape[0]
    out = np.empty(n)
    out[:k] = _combine_each(detector.novelty_rule, efficacy[:k], None if distances is None else distances[:k],
                            scales)
    if k < m:  # learned in the same call, the calibration full
        out[k:m] = detector._combine(efficacy[k:], None if distances is None else distances[k:m])
    if m < n:  # left to the engine chosen now
        out[m:] = detector._learn(X[m:], dt[m:])
    return out


def _combine_each(rule: str, efficacy: np.ndarray, distances: np.ndarray | None, scales: list) -> np.ndarray:
    """The novelty of scans each with its own scale (None: the efficacy alone), in one pass:
    the same operations on each element as one scan at a time."""
    if rule == "efficacy":
        return efficacy
    known = np.array([s is not None for s in scales], dtype=bool)
    sigma = np.array([1.0 if s is None else s for s in scales], dtype=np.float64)
    novelty = mismatch_novelty if rule == "mismatch" else product_novelty
    return np.where(known, novelty(efficacy, distances, sigma), efficacy)
