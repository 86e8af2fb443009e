"""The conformance checks every novelty detector must pass (run through :mod:`novelty.testing.conformance`)."""

from __future__ import annotations

import importlib.util
import tempfile
from pathlib import Path

import numpy as np
from sklearn.base import clone

from ..conformal import conformal_p_values, conformal_threshold
from ..detector import NoveltyDetector
from ..persistence import load
from ..registry import detectors
from ._helpers import _assert_same_state, _check, _rows, _state_arrays

__all__ = ["installed_detectors"]

def installed_detectors() -> list[str]:
    """Registered detector names whose optional dependencies (``requires``) are installed."""
    return [name for name in detectors.names()
            if all(importlib.util.find_spec(m) is not None for m in getattr(detectors.make(name), "requires", ()))]


@_check
def check_detector_fit_and_novelty(d: NoveltyDetector) -> None:
    X = _rows(d)
    det = clone(d).fit(X)
    out = det.novelty(X)
    assert out.shape == (X.shape[0],) and np.all(np.isfinite(out))
    assert det.n_features_in_ == X.shape[1]
    assert np.array_equal(det.score_samples(X), -out), "score_samples is -novelty"
    pred = det.predict(X)
    assert set(np.unique(pred)) <= {-1, 1}
    assert np.array_equal(pred == -1, out > det.threshold)


@_check
def check_detector_novelty_is_pure(d: NoveltyDetector) -> None:
    X = _rows(d)
    det = clone(d).fit(X)
    before = _state_arrays(det)
    first = det.novelty(X)
    det.score_one(X[0])
    det.predict(X)
    _assert_same_state(before, _state_arrays(det), "scoring must not change the model")
    assert np.array_equal(first, det.novelty(X))
    # one scan alone: a detector given the recent past reads the rows of a batch as a sequence
    assert np.isclose(det.score_one(X[3]), det.novelty(X[3:4])[0], rtol=1e-12, atol=1e-12), \
        "score_one equals novelty()"


@_check
def check_detector_deterministic(d: NoveltyDetector) -> None:
    X = _rows(d)
    a, b = clone(d).fit(X), clone(d).fit(X)
    assert np.array_equal(a.novelty(X), b.novelty(X)), "same parameters and data, same novelty"


@_check
def check_detector_rejects_bad_input(d: NoveltyDetector) -> None:
    X = _rows(d)
    det = clone(d).fit(X)
    before = _state_arrays(det)
    methods = ("novelty", "partial_fit", "fit") if det.supports_online else ("novelty", "fit")
    cases = [(X[:, :-1], [m for m in methods if m != "fit"])]  # a refit may change width
    cases += [(bad, methods) for bad in (np.full_like(X[:3], np.nan), np.empty((0, X.shape[1])), X[None])]
    for bad, names in cases:
        for method in names:
            try:
                getattr(det, method)(bad)
            except ValueError:
                pass
            else:
                raise AssertionError(f"{method} accepted bad input of shape {bad.shape}")
            _assert_same_state(before, _state_arrays(det), f"a rejected {method} must leave the model unchanged")


@_check
def check_detector_online(d: NoveltyDetector) -> None:
    if not d.supports_online:
        return
    X = _rows(d)
    # Start both from the same state: some networks initialise from the first batch.
    a, b = clone(d).fit(X[:20]), clone(d).fit(X[:20])
    streamed = a.stream(X[20:])
    one_by_one = np.array([b.score_learn_one(x) for x in X[20:]])
    assert np.allclose(streamed, one_by_one, rtol=1e-12, atol=1e-12), "stream() equals score_learn_one() row by row"
    _assert_same_state(_state_arrays(a), _state_arrays(b), "stream() and score_learn_one() must learn alike")


@_check
def check_detector_save_load(d: NoveltyDetector) -> None:
    X = _rows(d)
    det = clone(d).fit(X[:80])
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model.npz"
        det.save(path)
        back = load(path)
    assert type(back) is type(det)
    assert np.array_equal(det.novelty(X), back.novelty(X)), "a loaded model scores identically"
    if det.supports_online:
        assert np.array_equal(det.stream(X[80:]), back.stream(X[80:])), "and learns identically"


@_check
def check_detector_calibrate(d: NoveltyDetector) -> None:
    X = _rows(d)
    det = clone(d).fit(X[:80])
    det.calibrate(X[80:], false_alarm_rate=0.1, source="the checks' rows")
    familiar = det.novelty(X[80:])
    assert det.threshold_ == conformal_threshold(familiar, 0.1), "threshold_ is the conformal threshold"
    assert det.familiar_scores_.size == X.shape[0] - 80 and det.false_alarm_rate_ == 0.1
    p = det.p_values(X)
    assert np.array_equal(p, conformal_p_values(det.novelty(X), familiar))
    assert np.array_equal(det.predict(X) == -1, p <= 0.1), "an alarm exactly where p <= the rate"
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model.npz"
        det.save(path)
        back = load(path)
    assert back.threshold_ == det.threshold_ and back.calibrated_on_ == det.calibrated_on_, \
        "a loaded model keeps its calibration"
    det.fit(X[:80])
    assert not hasattr(det, "familiar_scores_"), "a refit is a new model: uncalibrated"
