"""The parts' parameters after fitting: learning on is refused while they differ from the fitted."""

import numpy as np
import pytest

import novelty


def data(n=60, d=4, seed=0):
    return np.random.default_rng(seed).uniform(size=(n, d))


def small(**params):
    return novelty.make("hsom", n_rows=4, n_columns=5, **params)


def test_part_parameters_changed_after_fitting_refuse_learning_until_refit(tmp_path):
    X = data()
    det = small().fit(X)
    before = det.synapse_.efficacy_.copy()
    det.set_params(synapse__alpha=1.5)
    for learn in (lambda: det.learn_one(X[0]), lambda: det.partial_fit(X[:3]), lambda: det.stream(X[:3])):
        with pytest.raises(ValueError, match=r"synapse__alpha changed after fitting.*Refit"):
            learn()
    np.testing.assert_array_equal(det.synapse_.efficacy_, before)  # nothing learned
    assert det.novelty(X).shape == (60,)  # scoring reads the fitted state
    det.save(tmp_path / "m.npz")
    with pytest.raises(ValueError, match="synapse__alpha changed after fitting"):
        novelty.load(tmp_path / "m.npz").learn_one(X[0])  # the same after a round trip
    det.fit(X)  # a refit learns with the new value
    assert det.synapse_.alpha == 1.5
    det.learn_one(X[0])
    det.set_params(clusterer__learning_rate=0.5, synapse__alpha=1.5)
    with pytest.raises(ValueError, match=r"clusterer__learning_rate changed"):
        det.learn_one(X[0])
    det.set_params(clusterer__learning_rate=0.25)  # set back: learning goes on
    det.learn_one(X[0])


def test_a_nan_part_parameter_is_refused_alike_by_every_learning_call():
    X = data()
    for learn in (lambda d: d.learn_one(X[0]), lambda d: d.stream(X[:3]), lambda d: d.fit(X)):
        det = small().fit(X)
        det.set_params(synapse__alpha=float("nan"))
        with pytest.raises(ValueError, match="alpha"):
            learn(det)
        unfitted = small(synapse__alpha=float("nan"))
        with pytest.raises(ValueError, match="alpha"):
            learn(unfitted)
