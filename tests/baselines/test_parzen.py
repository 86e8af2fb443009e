"""The Parzen window detector: bandwidth rules by hand, densities equal to scikit-learn's, a leave-one-out reference."""

import numpy as np
import pytest
from sklearn.neighbors import KernelDensity

from novelty.baselines import ParzenDetector


def test_bandwidth_rules_by_hand(blobs):
    n, d = blobs.shape
    sigma = np.sqrt(blobs.var(axis=0, ddof=1).mean())
    assert ParzenDetector().fit(blobs).bandwidth_ == pytest.approx(sigma * n ** (-1 / 6), rel=1e-12)
    silverman = sigma * (4 / (d + 2)) ** (1 / (d + 4)) * n ** (-1 / (d + 4))
    assert ParzenDetector(bandwidth="silverman").fit(blobs).bandwidth_ == pytest.approx(silverman, rel=1e-12)
    assert ParzenDetector(bandwidth=0.25).fit(blobs).bandwidth_ == 0.25


def test_parzen_density_equals_kernel_density(blobs, far):
    det = ParzenDetector().fit(blobs)
    kde = KernelDensity(kernel="gaussian", bandwidth=det.bandwidth_).fit(blobs)
    X = np.vstack([blobs[::5], far, [[2.5, 2.5]]])
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


@pytest.mark.parametrize("bandwidth", [1e155, 1e-200])
def test_a_bandwidth_whose_square_leaves_the_floats_is_a_value_error(blobs, bandwidth):
    # h^2 overflows above about 1e154; below about 1e-154 it is 0 and every density is damaged
    with pytest.raises(ValueError, match=r"'bandwidth' parameter of ParzenDetector must be .* \[1e-50, 1e\+150\]"):
        ParzenDetector(bandwidth=bandwidth).fit(blobs)
