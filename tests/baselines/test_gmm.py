"""GMM, Parzen window and SOM distance: known densities, known distances, far points."""

import numpy as np
import pytest
from sklearn.mixture import GaussianMixture
from sklearn.neighbors import KernelDensity

import novelty
from novelty.baselines import GaussianMixtureDetector, ParzenDetector, SOMDistance
from novelty.clusterers.som import SOM


@pytest.fixture(scope="module")
def blobs():
    rng = np.random.default_rng(1)
    centres = np.array([[0.0, 0.0], [5.0, 0.0], [0.0, 5.0]])
    return np.vstack([rng.normal(c, 0.3, size=(120, 2)) for c in centres])


FAR = np.array([[20.0, -20.0]])


@pytest.fixture(scope="module")
def gmm(blobs):
    """The default detector (K chosen by BIC over 1..10), fitted once."""
    return GaussianMixtureDetector().fit(blobs)


@pytest.mark.parametrize("det", [GaussianMixtureDetector(n_components=3), ParzenDetector(), SOMDistance(n_epochs=3),
                                 SOMDistance(clusterer=SOM(n_rows=4, n_columns=4, init="sample"))],
                         ids=["gmm", "parzen", "som-distance", "som-distance-sample"])
def test_a_far_point_is_more_novel_than_every_training_point(det, blobs):
    det.fit(blobs)
    assert det.raw_novelty(FAR)[0] > det.raw_novelty(blobs).max()
    assert det.novelty(FAR)[0] > det.novelty(blobs).max()
    assert det.predict(FAR)[0] == -1


# ------------------------------------------------------------------------ GMM
def test_bic_picks_the_number_of_well_separated_clusters(gmm):
    det = gmm
    assert det.n_components_ == 3
    assert det.bic_.shape == (10,) and int(np.argmin(det.bic_)) + 1 == 3
    one = GaussianMixtureDetector(max_components=4).fit(np.random.default_rng(2).normal(size=(300, 2)))
    assert one.n_components_ == 1


def test_given_number_of_components_is_used(blobs):
    det = GaussianMixtureDetector(n_components=2).fit(blobs)
    assert det.n_components_ == 2 and det.bic_.shape == (1,)


@pytest.mark.parametrize("kind", ["full", "tied", "diag", "spherical"])
def test_log_likelihood_from_the_stored_arrays_equals_scikit_learns(blobs, kind):
    det = GaussianMixtureDetector(n_components=3, covariance_type=kind).fit(blobs)
    ref = GaussianMixture(n_components=3, covariance_type=kind, random_state=0).fit(blobs)
    X = np.vstack([blobs[::7], FAR, [[2.5, 2.5]]])
    assert np.allclose(det.log_likelihood(X), ref.score_samples(X), rtol=1e-10, atol=1e-8)
    assert np.allclose(det.raw_novelty(X), -ref.score_samples(X), rtol=1e-10, atol=1e-8)


def test_gmm_scores_a_gap_between_clusters_as_novel(gmm, blobs):
    det = gmm
    assert det.novelty([[2.5, 2.5]])[0] > 0.999
    assert np.median(det.novelty(blobs)) == pytest.approx(0.5, abs=0.02)


# --------------------------------------------------------------------- Parzen
def test_bandwidth_rules_by_hand(blobs):
    n, d = blobs.shape
    sigma = np.sqrt(blobs.var(axis=0, ddof=1).mean())
    assert ParzenDetector().fit(blobs).bandwidth_ == pytest.approx(sigma * n ** (-1 / 6), rel=1e-12)
    silverman = sigma * (4 / (d + 2)) ** (1 / (d + 4)) * n ** (-1 / (d + 4))
    assert ParzenDetector(bandwidth="silverman").fit(blobs).bandwidth_ == pytest.approx(silverman, rel=1e-12)
    assert ParzenDetector(bandwidth=0.25).fit(blobs).bandwidth_ == 0.25


def test_parzen_density_equals_kernel_density(blobs):
    det = ParzenDetector().fit(blobs)
    kde = KernelDensity(kernel="gaussian", bandwidth=det.bandwidth_).fit(blobs)
    X = np.vstack([blobs[::5], FAR, [[2.5, 2.5]]])
    assert np.allclose(det.log_density(X), kde.score_samples(X), rtol=1e-10, atol=1e-10)


def test_parzen_reference_is_leave_one_out(blobs):
    det = ParzenDetector().fit(blobs)
    n, d = blobs.shape
    h = det.bandwidth_
    p = np.exp(det.log_density(blobs))
    self_kernel = (2 * np.pi * h * h) ** (-d / 2)
    loo = (n * p - self_kernel) / (n - 1)
    assert np.allclose(np.sort(det.reference_), np.sort(-np.log(loo)), rtol=1e-9)
    assert np.all(det.reference_ > det.raw_novelty(blobs).min()), "leave-one-out is never denser"


def test_far_point_keeps_a_finite_ordered_score():
    det = ParzenDetector().fit(np.random.default_rng(0).normal(size=(100, 3)))
    raw = det.raw_novelty([[50.0, 0, 0], [100.0, 0, 0]])
    assert np.all(np.isfinite(raw)) and raw[1] > raw[0]


# --------------------------------------------------------------- SOM distance
def test_som_distance_is_the_distance_to_the_best_matching_unit(blobs):
    det = SOMDistance(clusterer=SOM(n_rows=3, n_columns=3, init="sample")).fit(blobs)
    assert isinstance(det.clusterer_, SOM)
    W = det.clusterer_.weights_
    X = np.vstack([blobs[::11], FAR])
    expected = np.sqrt(((X[:, None, :] - W[None]) ** 2).sum(axis=2).min(axis=1))
    assert np.allclose(det.raw_novelty(X), expected, rtol=1e-10)


def test_som_distance_learns_online_before_scoring():
    det = SOMDistance(clusterer=SOM(n_rows=1, n_columns=1, learning_rate=0.5, init="uniform",
                                    init_range=(0.0, 1e-12)))
    assert det.score_learn_one([1.0, 0.0]) == 1.0  # first scan of a stream: fully novel
    assert det.raw_novelty([[1.0, 0.0]])[0] == pytest.approx(0.5, abs=1e-9)  # the unit moved half way
    det.learn_one([1.0, 0.0])
    assert det.raw_novelty([[1.0, 0.0]])[0] == pytest.approx(0.25, abs=1e-9)


def test_som_distance_takes_any_clusterer_by_name(blobs):
    det = SOMDistance(clusterer="gng", n_epochs=2).fit(blobs)
    assert novelty.registry.clusterers.name_of(det.clusterer_) == "gng"
    assert det.raw_novelty(FAR)[0] > det.raw_novelty(blobs).max()
