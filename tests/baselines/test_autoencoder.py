"""The autoencoder filter: reconstruction error of a small MLP, evaluated from stored arrays."""

import numpy as np
import pytest
from sklearn.neural_network import MLPRegressor

import novelty
from novelty.baselines import AutoencoderFilter


@pytest.fixture(scope="module")
def curve():
    t = np.random.default_rng(0).random((200, 1))
    return np.hstack([t, 1 - t, 0.5 * t, np.full_like(t, 0.2)])  # a line segment in R^4


@pytest.mark.parametrize("activation", ["tanh", "relu", "logistic", "identity"])
def test_reconstruction_from_the_stored_arrays_equals_the_mlp(curve, activation):
    det = AutoencoderFilter(hidden_layer_sizes=(3, 2), activation=activation, max_iter=200).fit(curve)
    net = MLPRegressor(hidden_layer_sizes=(3, 2), activation=activation, solver="lbfgs", alpha=1e-4,
                       max_iter=200, random_state=0).fit(curve, curve)
    X = np.vstack([curve[:10], [[0.9, 0.9, 0.0, 0.9]]])
    assert np.allclose(det.reconstruct(X), net.predict(X), rtol=1e-12, atol=1e-12)
    assert np.allclose(det.raw_novelty(X), np.linalg.norm(X - net.predict(X), axis=1), rtol=1e-12)
    assert det.layer_sizes_ == [4, 3, 2, 4]
    assert det.parameters_.shape == (4 * 3 + 3 + 3 * 2 + 2 + 2 * 4 + 4,)


def test_default_bottleneck_is_half_the_inputs():
    det = AutoencoderFilter().fit(np.random.default_rng(0).random((50, 6)))
    assert det.layer_sizes_ == [6, 3, 6]


def test_off_the_familiar_manifold_is_novel(curve):
    det = AutoencoderFilter(hidden_layer_sizes=(2,)).fit(curve)
    off = np.array([[0.9, 0.9, 0.0, 0.9], [0.0, 0.0, 1.0, 1.0]])
    assert det.raw_novelty(off).min() > 10 * det.raw_novelty(curve).mean()
    assert np.all(det.predict(off) == -1)


def test_batch_only(curve):
    det = AutoencoderFilter(max_iter=50).fit(curve)
    assert not det.supports_online and not hasattr(det, "partial_fit")
    with pytest.raises(TypeError, match="batch only"):
        det.stream(curve[:3])


def test_saved_model_holds_only_arrays_and_scores_identically(curve, tmp_path):
    det = AutoencoderFilter(hidden_layer_sizes=(2,)).fit(curve)
    arrays, values, children = det._export_state()
    assert set(arrays) == {"parameters_", "reference_", "decision_scores_"} and not children
    det.save(tmp_path / "ae.npz")
    back = novelty.load(tmp_path / "ae.npz")
    assert np.array_equal(back.novelty(curve), det.novelty(curve))


@pytest.mark.parametrize("sizes", [(), (0,), (2, -1), "3"])
def test_bad_hidden_layer_sizes_are_named(sizes):
    with pytest.raises(ValueError, match="'hidden_layer_sizes' parameter of AutoencoderFilter"):
        AutoencoderFilter(hidden_layer_sizes=sizes).fit(np.zeros((5, 2)))
