"""PyOD models by name: PyOD's own scores, put on the comparable scale, saved and reloaded."""

import sys

import numpy as np
import pytest

import novelty
from novelty._component import StateError
from novelty.baselines._calibration import comparable
from novelty.registry import InvalidParameterError

try:
    import pyod  # noqa: F401

    HAVE_PYOD = True
except ImportError:
    HAVE_PYOD = False

needs_pyod = pytest.mark.skipif(not HAVE_PYOD,
                                reason="PyOD is not installed (optional extra: novelty-habituation[pyod])")

MODELS = ["ECOD", "IForest", "KNN"]


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(0)
    X = rng.normal(size=(150, 3))
    Z = np.vstack([rng.normal(size=(5, 3)), rng.normal(size=(5, 3)) + 6.0])  # 5 familiar, 5 far away
    return X, Z


def pyod_model(name, **params):
    from pyod.models.ecod import ECOD
    from pyod.models.iforest import IForest
    from pyod.models.knn import KNN

    return {"ECOD": ECOD, "IForest": IForest, "KNN": KNN}[name](**params)


@needs_pyod
@pytest.mark.parametrize("model", MODELS)
def test_raw_novelty_is_pyods_decision_function_calibrated_on_its_training_scores(model, data):
    X, Z = data
    det = novelty.make("pyod", model=model).fit(X)
    ref = pyod_model(model, **({"random_state": 0} if model == "IForest" else {})).fit(X)
    # a batch is scored in one call, as PyOD scores it (ECOD's included, which depends on the batch)
    expected_raw = ref.decision_function(Z)
    np.testing.assert_allclose(det.raw_novelty(Z), expected_raw, rtol=1e-12)
    np.testing.assert_allclose(det.novelty(Z), comparable(expected_raw, ref.decision_scores_), rtol=1e-12)


@needs_pyod
@pytest.mark.parametrize("model", MODELS)
def test_far_away_scans_are_novel_and_familiar_ones_are_not(model, data):
    X, Z = data
    det = novelty.make("pyod", model=model).fit(X)
    nov = det.novelty(Z)
    assert np.all((0 <= nov) & (nov <= 1))
    assert nov[5:].min() > 0.99 and nov[:5].max() < nov[5:].min()
    np.testing.assert_array_equal(det.predict(Z)[5:], -1)


@needs_pyod
def test_a_transductive_model_scores_a_batch_as_pyod_does_and_one_scan_alone(data):
    X, Z = data
    det = novelty.make("pyod", model="ECOD").fit(X)
    ref = pyod_model("ECOD").fit(X)
    assert det.raw_novelty(Z)[0] != det.raw_novelty(Z[:1])[0]          # ECOD's scores depend on the batch
    assert det.score_one(Z[7]) == pytest.approx(comparable(ref.decision_function(Z[7:8]), ref.decision_scores_)[0],
                                                rel=1e-12)


@needs_pyod
def test_a_pyod_detector_object_is_used_as_it_is(data):
    from pyod.models.knn import KNN

    X, Z = data
    det = novelty.baselines.PyODDetector(model=KNN(n_neighbors=7, method="mean")).fit(X)
    ref = KNN(n_neighbors=7, method="mean").fit(X)
    np.testing.assert_allclose(det.raw_novelty(Z), ref.decision_function(Z), rtol=1e-12)
    with pytest.raises(StateError, match="cannot be saved"):
        det.save("unused.npz")


@needs_pyod
@pytest.mark.parametrize("model, params", [("ECOD", {}), ("IForest", {"n_estimators": 20}),
                                           ("KNN", {"n_neighbors": 7, "method": "mean"})])
def test_saved_model_is_refitted_identically(model, params, data, tmp_path):
    X, Z = data
    det = novelty.make("pyod", model=model, **params, contamination=0.1).fit(X)
    det.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    assert back.get_params() == det.get_params()
    assert back.novelty(Z).tobytes() == det.novelty(Z).tobytes()
    assert back.threshold_ == det.threshold_


@needs_pyod
def test_contamination_flags_that_fraction_of_the_training_scans(data):
    X, _ = data
    det = novelty.make("pyod", model="KNN", contamination=0.1).fit(X)
    assert det.labels_.sum() == 15
    np.testing.assert_array_equal(det.predict(X) == -1, det.labels_ == 1)


def test_model_parameters_are_routed_and_checked():
    det = novelty.make("pyod", model="KNN", n_neighbors=10, threshold=0.9)
    assert det.model_params == {"n_neighbors": 10} and det.threshold == 0.9
    if not HAVE_PYOD:
        pytest.skip("PyOD is not installed (optional extra: novelty-habituation[pyod]); "
                    "the rest checks PyOD's signatures")
    X = np.random.default_rng(0).normal(size=(30, 2))
    with pytest.raises(InvalidParameterError, match=r"'n_neighbour' \(did you mean 'n_neighbors'\?\) for the PyOD "
                                                    r"model KNN"):
        novelty.make("pyod", model="KNN", n_neighbour=10).fit(X)
    with pytest.raises(ValueError, match=r"sets the model's 'contamination' itself"):
        novelty.make("pyod", model="KNN", model_params={"contamination": 0.2}).fit(X)
    with pytest.raises(ValueError, match=r"must name a PyOD detector class.*Got 'EDOC'"):
        novelty.make("pyod", model="EDOC").fit(X)
    assert type(novelty.make("pyod", model="iforest").fit(X)._estimator).__name__ == "IForest"


def test_without_pyod_fit_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "pyod", None)  # import pyod now raises ImportError
    monkeypatch.setitem(sys.modules, "pyod.models", None)
    monkeypatch.setitem(sys.modules, "pyod.models.base", None)
    det = novelty.make("pyod")
    with pytest.raises(ImportError, match=r'pip install "novelty-habituation\[pyod\]"'):
        det.fit(np.zeros((5, 2)))
    assert not hasattr(det, "n_features_in_")


def test_set_params_routes_a_models_parameter_as_make_does():
    det = novelty.make("pyod", model="KNN", n_neighbors=10)
    assert det.set_params(n_neighbors=5, method="mean", threshold=0.8) is det
    assert det.model_params == {"n_neighbors": 5, "method": "mean"} and det.threshold == 0.8
    assert "n_neighbors" not in det.get_params()  # reported once, inside model_params
    assert det.set_params(model_params={"n_neighbors": 3}, method="median").model_params == {
        "n_neighbors": 3, "method": "median"}
