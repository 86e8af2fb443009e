"""Kohonen & Oja's novelty filter: the component of x outside the familiar subspace."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.baselines import KohonenNoveltyFilter

D, K = 16, 3


@pytest.fixture(scope="module")
def subspace():
    rng = np.random.default_rng(0)
    U = np.linalg.qr(rng.normal(size=(D, K)))[0]  # orthonormal basis of a 3-D subspace of R^16
    P = U @ U.T
    train = rng.normal(size=(400, K)) @ U.T
    inside = rng.normal(size=(200, K)) @ U.T
    outside = rng.normal(size=(200, D))
    return P, train, inside, outside


def test_pca_filter_inside_zero_outside_the_orthogonal_component(subspace):
    P, train, inside, outside = subspace
    det = KohonenNoveltyFilter(method="pca", n_components=3).fit(train)
    assert det.n_components_ == 3
    assert det.raw_novelty(inside).max() < 1e-12
    expected = np.linalg.norm(outside - outside @ P, axis=1)  # about sqrt(13) each: 3.48 on average
    assert np.allclose(det.raw_novelty(outside), expected, rtol=1e-12)
    assert expected.mean() == pytest.approx(3.479, abs=1e-3)
    assert np.allclose(det.filter_, np.eye(D) - P, atol=1e-12)


def test_pca_energy_share_chooses_the_subspace(subspace):
    _, train, _, _ = subspace
    assert KohonenNoveltyFilter(method="pca").fit(train).n_components_ == 3  # the rest is rounding noise
    s = np.array([10.0, 5.0, 1.0, 0.1])
    X = np.diag(s)  # singular values 10, 5, 1, 0.1: energy shares .79, .20, .008, .00008
    assert KohonenNoveltyFilter(method="pca", n_components=0.9).fit(X).n_components_ == 2
    assert KohonenNoveltyFilter(method="pca", n_components=0.995).fit(X).n_components_ == 3


@pytest.mark.parametrize("n_epochs, tolerance", [(1, 0.02), (5, 0.004)])
def test_online_rule_converges_to_the_complement_projector(subspace, n_epochs, tolerance):
    P, train, inside, outside = subspace
    det = KohonenNoveltyFilter(n_epochs=n_epochs).fit(train)
    assert np.linalg.norm(det.filter_ - (np.eye(D) - P), 2) < tolerance
    rel_inside = det.raw_novelty(inside) / np.linalg.norm(inside, axis=1)
    assert rel_inside.max() < tolerance, "near-zero novelty inside the subspace"
    expected = np.linalg.norm(outside - outside @ P, axis=1)
    assert np.allclose(det.raw_novelty(outside), expected, rtol=tolerance)


def test_online_rule_by_hand():
    """Phi <- Phi - (alpha / |x|^2) x~ x~^T, x~ = Phi x, from Phi = I."""
    det = KohonenNoveltyFilter(learning_rate=0.5)
    assert det.score_learn_one([1.0, 0.0]) == 1.0  # nothing is familiar yet
    assert np.allclose(det.filter_, [[0.5, 0.0], [0.0, 1.0]])
    assert det.raw_novelty([[1.0, 0.0]])[0] == 0.5
    det.learn_one([1.0, 0.0])  # x~ = (0.5, 0): Phi_11 = 0.5 - 0.5 * 0.25
    assert np.allclose(det.filter_, [[0.375, 0.0], [0.0, 1.0]])
    det.learn_one([0.0, 2.0])  # x~ = (0, 2), |x|^2 = 4: Phi_22 = 1 - 0.5 * 4 / 4
    assert np.allclose(det.filter_, [[0.375, 0.0], [0.0, 0.5]])
    assert np.allclose(det.novelty_component([[2.0, 2.0]]), [[0.75, 1.0]])


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 60), d=st.integers(1, 6),
       rate=st.floats(0.01, 1.0))
def test_online_filter_stays_symmetric_with_eigenvalues_in_0_1(seed, n, d, rate):
    X = np.random.default_rng(seed).normal(size=(n, d))
    det = KohonenNoveltyFilter(learning_rate=rate).fit(X)
    phi = det.filter_
    assert np.allclose(phi, phi.T, atol=1e-12)
    eig = np.linalg.eigvalsh(phi)
    assert eig.min() > -1e-9 and eig.max() < 1 + 1e-9
    assert np.all(det.raw_novelty(X) <= np.linalg.norm(X, axis=1) + 1e-9)


def test_online_learns_on_and_pca_is_batch_only(subspace):
    _, train, inside, _ = subspace
    online = KohonenNoveltyFilter().fit(train[:50])
    before = online.raw_novelty(inside).mean()
    online.partial_fit(train[50:])
    assert online.raw_novelty(inside).mean() < before
    pca = KohonenNoveltyFilter(method="pca").fit(train)
    assert not hasattr(pca, "partial_fit")
    with pytest.raises(TypeError, match="batch only"):
        pca.learn_one(train[0])


def test_comparable_scale_ranks_outside_above_inside(subspace):
    _, train, inside, outside = subspace
    det = KohonenNoveltyFilter(n_epochs=5).fit(train)
    assert det.novelty(outside).min() > 0.999
    assert det.novelty(inside).max() < det.novelty(outside).min()
    assert np.all(det.predict(outside) == -1)
