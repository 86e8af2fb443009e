"""Learning while the match scale is calibrated: each scan scored with the scale of those before it.

A filter whose novelty rule (or clusterer) needs the match scale sigma and
was not given one calibrates it on the first ``calibration_scans`` scans it
learns (:class:`novelty.match_scale.ScaleCalibration`), one scan at a time, so
that the numbers do not depend on how the scans were batched: each scan is
scored with the scale of the scans before it (none before two distinct scans:
the efficacy alone), then added to the calibration. A clusterer that learns
by the scale (``Clusterer.uses_match_scale``: GWR's ``"auto"`` radius) learns
one scan at a time meanwhile, given each new scale; any other learns the
batch in one call, since its learning does not read the scale.
"""

from __future__ import annotations

import numpy as np

from ..match_scale import mismatch_novelty, product_novelty

__all__ = ["learn_calibrating"]


def learn_calibrating(detector, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
    """The novelty of the rows of ``X``, learned by ``detector`` while (and after) its
    calibration (``detector._calibration``, not full) takes them."""
    calibration = detector._calibration
    at_once = not detector.clusterer_.uses_match_scale
    n = X.shape[0]
    if at_once:
        efficacy, distances = detector._learn_raw(X, dt)
    else:
        efficacy = np.empty(n)
        distances = None if detector.novelty_rule == "efficacy" else np.empty(n)
    scales = []  # each calibrating scan's scale, combined at the end
    i = 0
    while i < n and not calibration.full:
        scales.append(detector.match_scale_)
        if not at_once:
            e, d = detector._learn_raw(X[i:i + 1], dt[i:i + 1])
            efficacy[i] = e[0]
            if distances is not None:
                distances[i] = d[0]
        if calibration.add(X[i]):
            detector.match_scale_ = calibration.scale
            if not at_once:
                detector._current_engine().calibrate(detector.match_scale_)
        i += 1
    detector.calibration_scans_ = calibration.scans
    out = np.empty(n)
    out[:i] = _combine_each(detector.novelty_rule, efficacy[:i],
                            None if distances is None else distances[:i], scales)
    if i < n:
        out[i:] = (detector._combine(efficacy[i:], distances[i:]) if at_once
                   else detector._combine(*detector._learn_raw(X[i:], dt[i:])))
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
