"""The comparable [0, 1] scale shared by the baselines."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import novelty
from novelty.baselines import GaussianMixtureDetector, KohonenNoveltyFilter, ParzenDetector, comparable
from novelty.baselines._calibration import _MAX_REFERENCE, summarise_reference

BASELINES = ["kohonen-filter", "autoencoder-filter", "gmm", "som-distance", "parzen", "isolation-forest",
             "one-class-svm", "lof", "knn", "elliptic-envelope"]


def test_comparable_by_hand():
    ref = [1.0, 2.0, 3.0, 4.0]  # F = 1/5, 2/5, 3/5, 4/5; lam = std = sqrt(1.25)
    lam = math.sqrt(1.25)
    c = comparable([1.0, 2.5, 4.0, 0.0, 5.0], ref)
    assert c[:3].tolist() == pytest.approx([0.2, 0.5, 0.8], abs=1e-15)
    assert c[3] == pytest.approx(0.2 * math.exp(-1 / lam), rel=1e-15)
    assert c[4] == pytest.approx(1 - 0.2 * math.exp(-1 / lam), rel=1e-15)


def test_ties_count_every_equal_reference_score():
    assert comparable([1.0, 2.0], [1.0, 1.0, 2.0]).tolist() == pytest.approx([0.5, 0.75])


def test_empty_reference_means_nothing_is_familiar():
    assert comparable([-5.0, 0.0, 7.0], []).tolist() == [1.0, 1.0, 1.0]


def test_constant_reference_uses_a_unit_tail_scale():
    c = comparable([2.0, 3.0, 1.0], [2.0, 2.0])
    assert c.tolist() == pytest.approx([2 / 3, 1 - math.exp(-1) / 3, 2 / 3 * math.exp(-1)])


@settings(max_examples=80, deadline=None)
@given(ref=st.lists(st.floats(-1e3, 1e3), min_size=1, max_size=50),
       raw=st.lists(st.floats(-1e4, 1e4), min_size=2, max_size=50))
def test_comparable_is_monotone_and_in_0_1(ref, raw):
    raw = np.sort(raw)
    c = comparable(raw, ref)
    assert np.all((c >= 0) & (c <= 1))
    assert np.all(np.diff(c) >= -1e-15)


def test_large_reference_is_summarised_by_spread_quantiles():
    scores = np.random.default_rng(0).normal(size=50_000)
    ref = summarise_reference(scores)
    assert ref.shape == (_MAX_REFERENCE,)
    assert np.allclose(np.sort(ref), np.quantile(scores, (np.arange(1000) + 0.5) / 1000))
    first = ref[:100]  # the slots online learning overwrites first
    assert first.min() < np.quantile(scores, 0.02) and first.max() > np.quantile(scores, 0.98)


def test_threshold_flags_about_the_complementary_share_of_familiar_inputs():
    """For inputs like the familiar ones, P(novelty > 0.95) is about 5 %, whatever the detector."""
    rng = np.random.default_rng(0)
    train, fresh = rng.normal(size=(600, 3)), rng.normal(size=(4000, 3))
    for det in (GaussianMixtureDetector(n_components=1), ParzenDetector()):
        det.fit(train)
        share = float(np.mean(det.predict(fresh) == -1))
        assert 0.03 < share < 0.075, (det, share)


@pytest.mark.parametrize("name", BASELINES)
def test_every_baseline_reports_the_calibrated_raw_score(name):
    X = np.random.default_rng(0).random((150, 4))
    det = novelty.make(name).fit(X)
    Z = np.vstack([X[:20], np.full((1, 4), 3.0)])
    raw = det.raw_novelty(Z)
    assert np.allclose(det.novelty(Z), comparable(raw, det.reference_), rtol=0, atol=1e-15)
    assert np.array_equal(det.predict(Z) == -1, det.novelty(Z) > det.threshold)
    assert det.threshold == 0.95
    assert 0.0 <= det.novelty(Z).min() and det.novelty(Z).max() <= 1.0


def test_online_learning_extends_the_reference_and_starts_fully_novel():
    rng = np.random.default_rng(0)
    det = KohonenNoveltyFilter()
    out = det.stream(rng.normal(size=(30, 5)))
    assert out[0] == 1.0 and det.reference_.shape == (30,)
    det.fit(rng.normal(size=(2000, 5)))
    assert det.reference_.shape == (1000,) and det.reference_next_ == 0
    before = det.reference_.copy()
    new = rng.normal(size=(3, 5))
    expected = det.raw_novelty(new[:1])  # the first one's raw score before learning it
    det.partial_fit(new)
    assert det.reference_next_ == 3, "the three oldest slots were replaced"
    assert det.reference_[0] == expected[0]
    assert np.array_equal(det.reference_[3:], before[3:])


def test_knots_a_subnormal_apart_give_a_finite_monotone_scale():
    # np.interp's slope 0.33 / 2.2e-313 overflows to inf; the scale must not.
    ref = [0.0, 2.2e-313, 4.4e-313]
    raw = np.array([-1.0, 0.0, 1.1e-313, 2.2e-313, 3.3e-313, 4.4e-313, 1.0])
    c = comparable(raw, ref)
    assert np.all(np.isfinite(c)) and np.all((c >= 0) & (c <= 1))
    assert np.all(np.diff(c) >= 0)
    assert c[1:6].tolist() == pytest.approx([0.25, 0.375, 0.5, 0.625, 0.75])
