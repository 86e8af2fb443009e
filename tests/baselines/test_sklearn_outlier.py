"""The scikit-learn outlier adapter and the four detectors registered through it."""

import json
import time

import numpy as np
import pytest
from sklearn.covariance import EllipticEnvelope
from sklearn.ensemble import IsolationForest
from sklearn.linear_model import SGDOneClassSVM
from sklearn.neighbors import LocalOutlierFactor
from sklearn.svm import OneClassSVM

import novelty
from novelty._component import StateError
from novelty.baselines import SklearnOutlierDetector, sklearn_outlier
from novelty.persistence import ModelFileError


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(0)
    return rng.normal(size=(200, 3)), np.vstack([rng.normal(size=(20, 3)), [[8.0, 8.0, 8.0]]])


REGISTERED = {
    "isolation-forest": IsolationForest(random_state=0),
    "one-class-svm": OneClassSVM(),
    "lof": LocalOutlierFactor(novelty=True),
    "elliptic-envelope": EllipticEnvelope(random_state=0),
}


@pytest.mark.parametrize("name", REGISTERED)
def test_raw_novelty_is_minus_score_samples(name, data):
    X, Z = data
    det = novelty.make(name).fit(X)
    ref = REGISTERED[name].fit(X)
    assert np.allclose(det.raw_novelty(Z), -ref.score_samples(Z), rtol=1e-12, atol=1e-12)
    assert det.novelty(Z[-1:])[0] > det.novelty(X).max(), "the far point is the most novel"


def test_lof_reference_is_the_training_outlier_factors(data):
    X, _ = data
    det = novelty.make("lof").fit(X)
    ref = LocalOutlierFactor(novelty=True).fit(X)
    assert np.allclose(np.sort(det.reference_), np.sort(-ref.negative_outlier_factor_), rtol=1e-12)


@pytest.mark.parametrize("name", REGISTERED)
def test_saved_model_is_refitted_identically(name, data, tmp_path):
    X, Z = data
    det = novelty.make(name).fit(X)
    arrays, _, children = det._export_state()
    assert set(arrays) == {"samples_", "reference_", "decision_scores_"} and not children, "no estimator object is saved"
    det.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    assert type(back) is type(det)
    assert np.array_equal(back.novelty(Z), det.novelty(Z))


def test_saving_needs_an_integer_seed(data, tmp_path):
    det = novelty.make("isolation-forest", random_state=None).fit(data[0])
    with pytest.raises(StateError, match="integer random_state"):
        det.save(tmp_path / "m.npz")


def test_any_estimator_can_be_wrapped_but_not_saved(data, tmp_path):
    X, Z = data
    det = SklearnOutlierDetector(SGDOneClassSVM(random_state=0)).fit(X)
    ref = SGDOneClassSVM(random_state=0).fit(X)
    assert np.allclose(det.raw_novelty(Z), -ref.score_samples(Z))
    det.set_params(estimator__nu=0.2)
    assert det.get_params()["estimator__nu"] == 0.2
    with pytest.raises(StateError, match="cannot be saved.*never pickled"):
        det.save(tmp_path / "m.npz")


def test_lof_without_novelty_mode_is_refused(data):
    with pytest.raises(ValueError, match="must have fit and score_samples"):
        SklearnOutlierDetector(LocalOutlierFactor()).fit(data[0])


def test_the_wrapped_estimator_is_not_modified(data):
    est = IsolationForest(n_estimators=10, random_state=0)
    SklearnOutlierDetector(est).fit(data[0])
    assert not hasattr(est, "estimators_"), "fit works on a clone"


# ------------------------------------------------------------- the cost of a load
def _with_meta_change(path, out, change):
    with np.load(path, allow_pickle=False) as npz:
        entries = {name: npz[name] for name in npz.files}
    meta = json.loads(entries["meta"].tobytes().decode("utf-8"))
    change(meta["root"], entries)
    entries["meta"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    with open(out, "wb") as fh:
        np.savez(fh, **entries)
    return out


@pytest.mark.parametrize("n_estimators", [10**6, 10**9, 2**31 - 1])
def test_a_small_file_declaring_a_huge_forest_is_refused_before_any_tree_grows(tmp_path, n_estimators):
    det = novelty.make("isolation-forest", n_estimators=5).fit(np.random.default_rng(0).uniform(size=(40, 3)))
    det.save(tmp_path / "m.npz")
    bad = _with_meta_change(tmp_path / "m.npz", tmp_path / "bad.npz",
                            lambda root, _: root["params"].update(n_estimators=n_estimators))
    assert bad.stat().st_size < 30_000
    started = time.perf_counter()
    with pytest.raises(ModelFileError, match=r"at most 256000 trees x samples"):
        novelty.load(bad)
    assert time.perf_counter() - started < 5  # refused before fitting (a 10**6-tree refit took over 75 s)


def test_training_inputs_beyond_the_refit_cap_are_refused_at_load_and_at_save(tmp_path, monkeypatch):
    monkeypatch.setattr(sklearn_outlier, "MAX_REFIT_SAMPLES", 30)  # the cap made small: the test stays fast
    X = np.random.default_rng(0).uniform(size=(40, 3))
    det = novelty.make("lof").fit(X)
    with pytest.raises(StateError, match=r"keeps 40 training inputs .* at most 30 inputs"):
        det.save(tmp_path / "m.npz")
    assert not (tmp_path / "m.npz").exists()
    monkeypatch.setattr(sklearn_outlier, "MAX_REFIT_SAMPLES", 40)
    det.save(tmp_path / "m.npz")
    monkeypatch.setattr(sklearn_outlier, "MAX_REFIT_SAMPLES", 30)
    with pytest.raises(ModelFileError, match=r"keeps 40 training inputs"):
        novelty.load(tmp_path / "m.npz")


@pytest.mark.parametrize("name, param, value", [("isolation-forest", "n_estimators", 2**70),
                                                ("one-class-svm", "degree", 10**12)])
def test_parameters_beyond_what_the_estimator_takes_are_a_value_error(name, param, value):
    with pytest.raises(ValueError, match=rf"'{param}' parameter .* must be an int in \[\d+, 2\*\*31 - 1\]"):
        novelty.make(name, **{param: value}).fit(np.random.default_rng(0).uniform(size=(20, 2)))


@pytest.mark.parametrize("name, cap, work", [("one-class-svm", "MAX_REFIT_KERNEL_WORK", 40 * 40 * 3),
                                             ("elliptic-envelope", "MAX_REFIT_COVARIANCE_WORK", 40 * 3 * 3)])
def test_a_refit_beyond_its_work_cap_is_refused(tmp_path, monkeypatch, name, cap, work):
    det = novelty.make(name).fit(np.random.default_rng(0).normal(size=(40, 3)))
    monkeypatch.setattr(sklearn_outlier, cap, work)  # exactly at the cap: saved and read
    det.save(tmp_path / "m.npz")
    novelty.load(tmp_path / "m.npz")
    monkeypatch.setattr(sklearn_outlier, cap, work - 1)
    with pytest.raises(ModelFileError, match=rf"{work} inputs.* a model file holds at most {work - 1}"):
        novelty.load(tmp_path / "m.npz")
