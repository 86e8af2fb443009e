"""Alarm policies on hand-made sequences of novelty scores, with the expected states."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import novelty
from novelty.alarms import Hysteresis, KOfN, Threshold, parse_alarm

F, T = False, True


def test_threshold_is_strict_as_predict():
    assert Threshold(0.5).run([0.4, 0.5, 0.5000001, 0.9]).tolist() == [F, F, T, T]


def test_threshold_agrees_with_a_detectors_predict():
    X = np.random.default_rng(0).uniform(size=(300, 4))
    det = novelty.make("hsom").fit(X)
    Y = np.random.default_rng(1).uniform(size=(50, 4))
    np.testing.assert_array_equal(Threshold(det.threshold_).run(det.novelty(Y)), det.predict(Y) == -1)


def test_k_of_n_counts_the_last_n_scans():
    scores = [0.9, 0.1, 0.9, 0.1, 0.1, 0.9, 0.9, 0.9, 0.1, 0.1]
    # above 0.5:   1    0    1    0    0    1    1    1    0    0
    # last 3:      1    1    2    1    1    1    2    3    2    1
    assert KOfN(2, 3, 0.5).run(scores).tolist() == [F, F, T, F, F, F, T, T, T, F]
    # last 5:      1    1    2    2    2    2    3    3    3    3    (window 0.9 0.9 0.9 0.1 0.1 at the end)
    assert KOfN(3, 5, Threshold(0.5)).run(scores).tolist() == [F, F, F, F, F, F, T, T, T, T]


def test_k_of_n_before_the_window_is_full_counts_what_it_saw():
    assert KOfN(2, 10, 0.5).run([0.9, 0.9, 0.1]).tolist() == [F, T, T]
    assert KOfN(1, 1, 0.5).run([0.9, 0.1, 0.9]).tolist() == [T, F, T]  # = Threshold(0.5)


def test_hysteresis_raises_above_high_and_clears_below_low():
    scores = [0.5, 0.8, 0.6, 0.4, 0.3, 0.2, 0.5, 0.7, 0.71, 0.29]
    expected = [F, T, T, T, T, F, F, F, T, F]  # 0.3 is not below 0.3; 0.7 is not above 0.7
    assert Hysteresis(high=0.7, low=0.3).run(scores).tolist() == expected
    # equal thresholds: a threshold whose state holds on the threshold itself
    assert Hysteresis(0.5, 0.5).run([0.6, 0.5, 0.4, 0.5]).tolist() == [T, T, F, F]


def test_policies_compose_k_of_n_over_hysteresis():
    scores = [0.8, 0.5, 0.5, 0.2, 0.8, 0.2, 0.2]
    # hysteresis(0.7, 0.3): T T T F T F F; 2 of the last 3 of those:
    assert KOfN(2, 3, Hysteresis(0.7, 0.3)).run(scores).tolist() == [F, T, T, T, T, F, F]


def test_run_continues_the_stream_and_reset_forgets_it():
    scores = [0.9, 0.1, 0.9, 0.1, 0.1, 0.9, 0.9]
    one = KOfN(2, 3, Hysteresis(0.7, 0.3))
    whole = one.run(scores)
    two = KOfN(2, 3, Hysteresis(0.7, 0.3))
    pieces = np.concatenate([two.run(scores[:2]), [two.update(scores[2])], two.run(scores[3:])])
    np.testing.assert_array_equal(whole, pieces)
    one.reset()
    np.testing.assert_array_equal(one.run(scores), whole)


@given(st.lists(st.floats(0, 1), max_size=40), st.integers(1, 6), st.integers(0, 5))
def test_k_of_n_equals_a_sliding_window_count(scores, n, k_less):
    k = max(1, n - k_less)
    above = np.array(scores) > 0.5
    expected = [above[max(0, i - n + 1):i + 1].sum() >= k for i in range(len(scores))]
    assert KOfN(k, n, 0.5).run(scores).tolist() == expected


@pytest.mark.parametrize("build, message", [
    (lambda: KOfN(0, 5, 0.5), r"The 'k' parameter of KOfN must be an int in \[1, 5\]. Got 0"),
    (lambda: KOfN(6, 5, 0.5), r"'k' parameter of KOfN must be an int in \[1, 5\]. Got 6"),
    (lambda: KOfN(1, 0, 0.5), r"'n' parameter of KOfN must be an int in \[1, inf\)"),
    (lambda: KOfN(2.0, 5, 0.5), r"'k' parameter"),
    (lambda: Hysteresis(0.3, 0.7), r"The 'low' parameter of Hysteresis must be a float in \(-inf, 0.3\]"),
    (lambda: Threshold(float("nan")), r"'threshold' parameter of Threshold"),
    (lambda: Threshold("0.5"), r"'threshold' parameter of Threshold"),
    (lambda: Threshold(0.5).update(float("nan")), r"takes novelty scores as numbers; got nan"),
    (lambda: Threshold(0.5).update("high"), r"got 'high'"),
])
def test_bad_parameters_and_scores_are_refused(build, message):
    with pytest.raises(ValueError, match=message):
        build()


@pytest.mark.parametrize("spec, threshold, expected", [
    ("threshold", 0.5, "Threshold(0.5)"),
    ("threshold:0.8", 0.5, "Threshold(0.8)"),
    ("k-of-n:3,5", 0.5, "KOfN(3, 5, Threshold(0.5))"),
    (" K-of-N:3,5,0.9 ", None, "KOfN(3, 5, Threshold(0.9))"),
    ("hysteresis:0.7,0.4", None, "Hysteresis(high=0.7, low=0.4)"),
])
def test_parse_alarm(spec, threshold, expected):
    assert repr(parse_alarm(spec, threshold)) == expected


@pytest.mark.parametrize("spec, message", [
    ("k-of-m:3,5", r"Unknown alarm 'k-of-m:3,5'; expected one of threshold\[:T\], k-of-n:K,N\[,T\]"),
    ("k-of-n:3", r"takes k-of-n:K,N\[,T\]; got 1 value"),
    ("hysteresis:0.7", r"takes hysteresis:HIGH,LOW; got 1 value"),
    ("k-of-n:3,x", r"must be numbers separated by commas"),
    ("k-of-n:2.5,5", r"whole numbers of scans; got 2.5 and 5"),
    ("k-of-n:inf,5", r"whole numbers of scans; got inf and 5"),
    ("k-of-n:3,5", r"needs a threshold"),
    ("k-of-n:6,5,0.5", r"'k' parameter of KOfN"),
])
def test_parse_alarm_refuses_bad_forms(spec, message):
    with pytest.raises(ValueError, match=message):
        parse_alarm(spec)
