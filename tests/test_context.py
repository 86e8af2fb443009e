"""Sequence context: the embedding and the integration by hand, streaming equals batches, files."""

import math

import numpy as np
import pytest

import novelty
from novelty._component import StateError
from novelty.context import SequenceContext, delay_embed, leaky_integrate
from novelty.registry import build

LINE = np.array([[0.0], [1.0], [3.0], [6.0]])


def test_registered_by_name():
    assert isinstance(build("detector", "context", delay=2), SequenceContext)


def test_the_detector_learns_the_embedded_scans():
    det = SequenceContext("nearest-memory", delay=2)
    det.stream(LINE)
    # (x_t, x_t-1), the first scan standing in for the one before it
    assert det.detector_.memory_.tolist() == [[0.0, 0.0], [1.0, 0.0], [3.0, 1.0], [6.0, 3.0]]
    assert det.history_.tolist() == [[6.0]]
    # the next scan, 6 again, is embedded as (6, 6): nearest (6, 3) at distance 3
    assert det.detector_.raw_novelty(det._embed(np.array([[6.0]]))).tolist() == [3.0]


def test_differences_and_lag_by_hand():
    past = np.array([[1.0], [2.0], [4.0]])
    got = delay_embed(np.array([[7.0], [11.0]]), past, delay=3, lag=1, differences=True)
    assert got.tolist() == [[7.0, 3.0, 5.0], [11.0, 4.0, 7.0]]
    got = delay_embed(np.array([[7.0]]), past, delay=2, lag=3, differences=False)
    assert got.tolist() == [[7.0, 1.0]]


def test_leaky_integration_by_hand():
    out = leaky_integrate(np.array([0.8, 0.0, 0.4]), 0.2, 0.25)
    # y1 = .75 * .2 + .25 * .8 = .35; y2 = .75 * .35 = .2625; y3 = .75 * .2625 + .1 = .296875
    np.testing.assert_allclose(out, [0.35, 0.2625, 0.296875], rtol=1e-15)


def test_smoothing_reports_the_integrated_novelty_of_the_detector():
    X = np.random.default_rng(0).random((40, 3))
    alone = novelty.make("gwr-explore").stream(X)
    det = SequenceContext("gwr-explore", smoothing=0.5)
    expected, y = [], None
    for n in alone:
        y = n if y is None else 0.5 * y + 0.5 * n
        expected.append(y)
    np.testing.assert_allclose(det.stream(X), expected, rtol=1e-12)
    assert math.isclose(det.level_, expected[-1])


def test_no_context_is_the_detector_alone():
    X = np.random.default_rng(1).random((60, 4))
    np.testing.assert_array_equal(SequenceContext("kmeans-stanley").stream(X),
                                  novelty.make("kmeans-stanley").stream(X))


@pytest.mark.parametrize("params", [{"delay": 3, "lag": 2}, {"delay": 2, "differences": True, "smoothing": 0.3}])
def test_scan_by_scan_equals_batches_and_survives_a_file(params, tmp_path):
    X = np.random.default_rng(2).random((90, 4))
    whole = SequenceContext("gwr-explore-wang-hsu", **params)
    out = whole.stream(X)
    pieces = SequenceContext("gwr-explore-wang-hsu", **params)
    parts = [pieces.stream(X[:30]), [pieces.score_learn_one(x) for x in X[30:60]]]
    pieces.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    parts.append(back.stream(X[60:]))
    np.testing.assert_array_equal(np.concatenate(parts), out)


def test_scoring_reads_a_batch_as_the_scans_that_follow_and_changes_nothing():
    X, Y = np.random.default_rng(3).random((50, 2)), np.random.default_rng(4).random((5, 2))
    det = SequenceContext("nearest-memory", delay=2, smoothing=0.5).fit(X)
    before = det.detector_.memory_.copy()
    first = det.novelty(Y)
    assert first[0] == det.score_one(Y[0])
    np.testing.assert_array_equal(det.novelty(Y), first)
    np.testing.assert_array_equal(det.detector_.memory_, before)


def test_a_batch_learner_is_fitted_on_the_embedded_scans():
    X = np.random.default_rng(5).random((80, 3))
    det = SequenceContext("parzen", delay=2).fit(X)
    assert not det.supports_online and det.detector_.n_features_in_ == 6


@pytest.mark.parametrize("params, message", [
    ({"delay": 0}, "delay"), ({"lag": 0}, "lag"), ({"smoothing": 0.0}, "smoothing"),
    ({"detector": 3}, "detector"), ({"differences": "yes"}, "differences"),
])
def test_bad_parameters_are_refused(params, message):
    with pytest.raises((ValueError, TypeError), match=message):
        SequenceContext(**params).fit(LINE)


@pytest.mark.parametrize("params, message", [
    ({"delay": 1025}, r"The 'delay' parameter of SequenceContext must be an int in \[1, 1024\]"),
    ({"lag": 2**21}, r"The 'lag' parameter of SequenceContext must be an int in \[1, 2\*\*20\]"),
    ({"delay": 1000, "lag": 2000}, r"keeps \(delay - 1\) \* lag scans of history, at most 1048576"),
])
def test_parameters_that_size_the_history_are_bounded(params, message):
    with pytest.raises(ValueError, match=message):
        SequenceContext("nearest-memory", **params).fit(np.zeros((3, 2)))


def test_a_history_too_large_for_its_features_is_refused_before_it_is_made():
    det = SequenceContext("nearest-memory", delay=2, lag=2**20)
    with pytest.raises(ValueError, match=r"would keep 1048576 scans of 200 features of history"):
        det.fit(np.zeros((3, 200)))


def test_a_state_without_its_level_is_refused():
    """A model file whose metadata lost ``level_`` loaded and then failed with AttributeError
    at the first score; it is refused when read, as every damaged state is."""
    det = SequenceContext("nearest-memory", delay=2).fit(np.random.default_rng(0).random((10, 2)))
    det._check_state()
    del det.level_
    with pytest.raises(StateError, match="missing 'level_'"):
        det._check_state()
