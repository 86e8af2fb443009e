"""The Gaussian mixture detector: the number of components by BIC, log-likelihoods equal to scikit-learn's."""

import numpy as np
import pytest
from sklearn.mixture import GaussianMixture

from novelty.baselines import GaussianMixtureDetector


@pytest.fixture(scope="module")
def gmm(blobs):
    """The default detector (K chosen by BIC over 1..10), fitted once."""
    return GaussianMixtureDetector().fit(blobs)


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
def test_log_likelihood_from_the_stored_arrays_equals_scikit_learns(blobs, kind, far):
    det = GaussianMixtureDetector(n_components=3, covariance_type=kind).fit(blobs)
    ref = GaussianMixture(n_components=3, covariance_type=kind, random_state=0).fit(blobs)
    X = np.vstack([blobs[::7], far, [[2.5, 2.5]]])
    assert np.allclose(det.log_likelihood(X), ref.score_samples(X), rtol=1e-10, atol=1e-8)
    assert np.allclose(det.raw_novelty(X), -ref.score_samples(X), rtol=1e-10, atol=1e-8)


def test_gmm_scores_a_gap_between_clusters_as_novel(gmm, blobs):
    det = gmm
    assert det.novelty([[2.5, 2.5]])[0] > 0.999
    assert np.median(det.novelty(blobs)) == pytest.approx(0.5, abs=0.02)
