"""Detectors in River's own composition: pipelines, progressive validation and River's checks."""

import numpy as np
import pytest

import novelty

river = pytest.importorskip("river")
from river import evaluate, metrics, preprocessing  # noqa: E402
from river.checks import anomaly as river_anomaly_checks  # noqa: E402
from river.checks import common as river_common_checks  # noqa: E402


def _stream(n=300, seed=0):
    """Scans of 4 features in [0, 10], every tenth far away (label 1): unscaled, as streams come."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        novel = i % 10 == 9
        values = 10 * rng.random(4) * (0.3 if not novel else 1.0) + (6.0 if novel else 0.0)
        out.append(({f"f{j}": float(v) for j, v in enumerate(values)}, int(novel)))
    return out


def test_a_detector_is_a_river_anomaly_detector():
    det = novelty.make("kmeans-stanley")
    assert isinstance(det, river.base.AnomalyDetector) and det._supervised is False


def test_a_scaler_and_a_detector_learn_and_score_in_a_river_pipeline():
    model = preprocessing.MinMaxScaler() | novelty.make("kmeans-stanley")
    scores = []
    for x, _ in _stream(60):
        scores.append(model.score_one(x))       # the first scan, scaled by nothing learned, is all NaN
        model.learn_one(x)
    assert scores[0] == 1.0 and all(np.isfinite(scores))
    assert model["HabituatingFilter"].n_features_in_ == 4


def test_progressive_val_score_runs_with_rocauc_and_gives_what_the_loop_gives():
    got = evaluate.progressive_val_score(_stream(), preprocessing.MinMaxScaler() | novelty.make("kmeans-stanley"),
                                         metrics.ROCAUC())
    # River's protocol by hand: score, update the metric, then learn, one scan after another
    model, metric = preprocessing.MinMaxScaler() | novelty.make("kmeans-stanley"), metrics.ROCAUC()
    for x, y in _stream():
        metric.update(y, model.score_one(x))
        model.learn_one(x)
    assert got.get() == metric.get() and got.get() > 0.8


def test_rivers_own_checks_of_learn_one_and_of_an_anomaly_detector_pass():
    stream = _stream(100)
    river_common_checks.check_learn_one(novelty.make("kmeans-stanley"), stream)
    river_anomaly_checks.check_roc_auc(preprocessing.MinMaxScaler() | novelty.make("kmeans-stanley"), stream)


def test_only_an_unlearned_detector_takes_a_scan_of_nan():
    det = novelty.make("kmeans-stanley")
    assert det.score_one({"a": float("nan"), "b": float("nan")}) == 1.0
    det.learn_one({"a": 0.2, "b": 0.4})
    with pytest.raises(ValueError, match="NaN"):
        det.score_one({"a": float("nan"), "b": float("nan")})
