"""Bad input and bad parameters: a clear ValueError, and the model exactly as it was."""

import copy
import numbers

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.exceptions import NotFittedError

import novelty
from novelty._validation import Bounds, Interval, Options, check_timestamps
from novelty.registry import clusterers

N_FEATURES = 4


def fitted():
    det = novelty.make("hsom", n_rows=3, n_columns=3)
    det.fit(np.random.default_rng(0).uniform(size=(20, N_FEATURES)))
    det.synapse_.efficacy_[:] = np.linspace(0.1, 0.9, 9)  # not all equal, so any change shows
    return det


def snapshot(det):
    """A deep copy of every attribute of the detector and of its fitted parts."""
    snap = {"detector": copy.deepcopy({k: v for k, v in vars(det).items() if k not in ("clusterer_", "synapse_")})}
    for part in ("clusterer_", "synapse_"):
        if hasattr(det, part):
            snap[part] = copy.deepcopy(vars(getattr(det, part)))
    return snap


def assert_equal_deep(a, b, where="state"):
    if isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray) and a.dtype == b.dtype, where
        np.testing.assert_array_equal(a, b, err_msg=where)
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            assert_equal_deep(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, (list, tuple)):
        assert type(a) is type(b) and len(a) == len(b), where
        for i, (u, v) in enumerate(zip(a, b)):
            assert_equal_deep(u, v, f"{where}[{i}]")
    elif hasattr(a, "get_params"):
        assert repr(a.get_params()) == repr(b.get_params()), where
    else:
        assert a == b, where


def row(value):
    x = [0.5] * N_FEATURES
    x[1] = value
    return x


BAD_BATCHES = {
    "wrong n_features": (np.zeros((3, N_FEATURES + 1)), r"X has 5 features, but HabituatingFilter is expecting 4 features"),
    "too few features": (np.zeros((3, N_FEATURES - 1)), r"X has 3 features, but HabituatingFilter is expecting 4"),
    "NaN": ([row(0.1), row(np.nan)], r"NaN or infinity \(first in row 1\).*expects finite numbers"),
    "inf": ([row(np.inf)], r"NaN or infinity"),
    "-inf": ([row(-np.inf), row(0.2)], r"NaN or infinity"),
    "empty": (np.zeros((0, N_FEATURES)), r"0 sample\(s\).*minimum of 1 is required"),
    "strings": ([["a", "b", "c", "d"]], r"expects X as a 2-D array of numbers.*not numeric"),
    "ragged": ([[1, 2, 3, 4], [1, 2]], r"expects X as a 2-D array of numbers"),
    "3-D": (np.zeros((2, 2, N_FEATURES)), r"dim 3.*dim <= 2"),
    "1-D": (np.zeros(N_FEATURES), r"Expected 2D array, got 1D array"),
    "norm above the bound": ([row(0.1), row(1e155)], r"norm above 1e\+100 \(first in row 1\).*rescale"),
    "finite but overflowing": ([row(1e308)], r"norm above 1e\+100"),
    "complex": (np.full((2, N_FEATURES), 1 + 1j), r"Complex data not supported.*real numbers"),
    "datetime64": (np.zeros((2, N_FEATURES), dtype="datetime64[s]"), r"real numbers; got dates"),
    "timedelta64 list": ([[np.timedelta64(1, "s")] * N_FEATURES], r"real numbers; got time spans"),
}

BAD_SCANS = {
    "wrong n_features": (np.zeros(N_FEATURES + 1), r"x has 5 features, but HabituatingFilter is expecting 4"),
    "NaN": (row(np.nan), r"contains NaN or infinity"),
    "inf": (np.array(row(np.inf)), r"contains NaN or infinity"),
    "empty": (np.zeros(0), r"empty scan"),
    "strings": (["a", "b", "c", "d"], r"1-D sequence of numbers; got values that are not numeric"),
    "2-D": (np.zeros((1, N_FEATURES)), r"1-D array of shape \(n_features,\).*shape \(1, 4\)"),
    "3-D": (np.zeros((1, 1, N_FEATURES)), r"1-D array of shape \(n_features,\)"),
    "scalar": (0.5, r"1-D array of shape \(n_features,\); got an array of shape \(\)"),
    "norm above the bound": (row(1e155), r"norm above 1e\+100.*rescale"),
    "complex": (np.array(row(0.5)) + 1j, r"Complex data not supported.*real numbers"),
    "complex list": ([0.5, 0.5, 0.5, 0.5j], r"Complex data not supported"),
    "datetime64": (np.zeros(N_FEATURES, dtype="datetime64[s]"), r"real numbers; got dates"),
}

BATCH_METHODS = ["partial_fit", "fit", "stream", "stream_nolearn", "novelty", "score_samples",
                 "decision_function", "predict", "winners", "fit_predict"]
ONE_METHODS = ["score_one", "learn_one", "score_learn_one"]


def call(det, method, X):
    if method == "stream_nolearn":
        return det.stream(X, learn=False)
    return getattr(det, method)(X)


@pytest.mark.parametrize(
    "method, case",
    [(m, c) for m in BATCH_METHODS for c in BAD_BATCHES
     # fit starts afresh: any number of features is valid there
     if not (m in ("fit", "fit_predict") and "features" in c)],
)
def test_bad_batch_is_refused_and_changes_nothing(method, case):
    X, message = BAD_BATCHES[case]
    det = fitted()
    before = snapshot(det)
    with pytest.raises(ValueError, match=message):
        call(det, method, X)
    assert_equal_deep(before, snapshot(det))


@pytest.mark.parametrize("method", ONE_METHODS)
@pytest.mark.parametrize("case", list(BAD_SCANS))
def test_bad_scan_is_refused_and_changes_nothing(method, case):
    x, message = BAD_SCANS[case]
    det = fitted()
    before = snapshot(det)
    with pytest.raises(ValueError, match=message):
        getattr(det, method)(x)
    assert_equal_deep(before, snapshot(det))


def test_the_callers_array_is_never_written_to():
    det = fitted()
    X = np.random.default_rng(1).uniform(size=(10, N_FEATURES))
    copy_ = X.copy()
    det.partial_fit(X)
    det.score_learn_one(X[0])
    np.testing.assert_array_equal(X, copy_)


# -------------------------------------------------- the first batch of a life
@pytest.mark.parametrize("method", ["fit", "partial_fit", "stream", "fit_predict"])
@pytest.mark.parametrize("case", [c for c in BAD_BATCHES if "features" not in c])
def test_bad_first_batch_leaves_the_model_unfitted(method, case):
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    before = snapshot(det)
    with pytest.raises(ValueError, match=BAD_BATCHES[case][1]):
        call(det, method, BAD_BATCHES[case][0])
    assert not hasattr(det, "n_features_in_")
    assert not hasattr(det, "clusterer_") and not hasattr(det, "synapse_")
    assert_equal_deep(before, snapshot(det))
    with pytest.raises(NotFittedError):
        det.novelty(np.zeros((1, N_FEATURES)))


@pytest.mark.parametrize("method", ["learn_one", "score_learn_one"])
@pytest.mark.parametrize("case", [c for c in BAD_SCANS if "features" not in c])
def test_bad_first_scan_leaves_the_model_unfitted(method, case):
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    with pytest.raises(ValueError, match=BAD_SCANS[case][1]):
        getattr(det, method)(BAD_SCANS[case][0])
    assert not hasattr(det, "n_features_in_") and not hasattr(det, "clusterer_")


@pytest.mark.parametrize("method", ["novelty", "score_samples", "decision_function", "predict", "winners"])
def test_unfitted_scoring_raises_not_fitted(method):
    det = novelty.make("hsom")
    with pytest.raises(NotFittedError, match="not fitted yet"):
        getattr(det, method)(np.zeros((1, 3)))
    with pytest.raises(NotFittedError):
        det.stream(np.zeros((1, 3)), learn=False)


# ----------------------------------------------------------- bad timestamps
@pytest.mark.parametrize(
    "timestamps, message",
    [
        ([3.0, 2.0], r"must not decrease"),
        ([0.0, np.nan], r"NaN or infinity"),
        ([0.0], r"one value per scan \(2\)"),
        ([[0.0, 1.0]], r"1-D array"),
        ([11.0, 12.0 + 1j], r"timestamps must be real numbers; got complex"),
        (np.array([11, 12], dtype="datetime64[s]"), r"timestamps must be real numbers; got dates"),
        ([11.0, "x"], r"timestamps must be numbers"),
    ],
)
def test_bad_timestamps_are_refused_and_change_nothing(timestamps, message):
    det = fitted()
    det.partial_fit(np.full((1, N_FEATURES), 0.5), timestamps=[10.0])
    before = snapshot(det)
    with pytest.raises(ValueError, match=message):
        det.partial_fit(np.full((2, N_FEATURES), 0.5), timestamps=timestamps)
    assert_equal_deep(before, snapshot(det))
    with pytest.raises(ValueError, match=r"must not decrease"):
        det.learn_one(np.full(N_FEATURES, 0.5), t=9.0)  # before the last scan learned
    assert_equal_deep(before, snapshot(det))


# ---------------------------------------------------------- bad parameters
@pytest.mark.parametrize(
    "params, message",
    [
        ({"threshold": "high"}, r"The 'threshold' parameter of HabituatingFilter must be a float in \(-inf, inf\)\. Got 'high' instead\."),
        ({"n_epochs": 0}, r"The 'n_epochs' parameter of HabituatingFilter must be an int in \[1, inf\)\. Got 0 instead\."),
        ({"stimulus": -1.0}, r"The 'stimulus' parameter of HabituatingFilter must be a float in \[0, inf\)"),
        ({"learning_rate": 2.0}, r"The 'learning_rate' parameter of SOM must be a float in \[0, 1\]\. Got 2\.0 instead\."),
        ({"n_rows": 0}, r"The 'n_rows' parameter of SOM must be an int in \[1, inf\)"),
        ({"tau_winner": -3.0}, r"The 'tau_winner' parameter of StanleySynapse must be a float in \(0, inf\)"),
        ({"tau_neighbour": 0.5}, r"The 'tau_neighbour' parameter of StanleySynapse must be >= alpha"),
        ({"others": "forgetful"}, r"The 'others' parameter of StanleySynapse must be one of 'hold', 'forget'"),
    ],
)
@pytest.mark.parametrize("method", ["fit", "partial_fit", "learn_one"])
def test_invalid_parameters_name_the_parameter_and_range_and_leave_it_unfitted(params, message, method):
    det = novelty.make("hsom", n_rows=2, n_columns=2, **{k: v for k, v in params.items() if k != "n_rows"})
    if "n_rows" in params:
        det.set_params(clusterer__n_rows=params["n_rows"])
    X = np.full((2, N_FEATURES), 0.5)
    with pytest.raises(ValueError, match=message):
        getattr(det, method)(X[0] if method == "learn_one" else X)
    assert not hasattr(det, "n_features_in_") and not hasattr(det, "clusterer_")
    assert not hasattr(det, "synapse_")


def test_a_refit_with_invalid_parameters_keeps_the_fitted_model():
    det = fitted()
    before = snapshot(det)
    det.synapse.set_params(tau_winner=0.1)  # the specification, not the fitted synapse_
    with pytest.raises(ValueError, match="'tau_winner' parameter of StanleySynapse"):
        det.fit(np.zeros((3, N_FEATURES)))
    after = snapshot(det)
    after["detector"].pop("synapse"), before["detector"].pop("synapse")
    assert_equal_deep(before, after)


def test_component_given_as_the_wrong_type_is_named():
    det = novelty.make("habituating", clusterer=novelty.StanleySynapse(), synapse="stanley")
    with pytest.raises(ValueError, match=r"The 'clusterer' parameter of HabituatingFilter must be a clusterer name or a Clusterer instance"):
        det.fit(np.zeros((2, 2)))


# ------------------------------------------------------------- the checks
@pytest.mark.parametrize(
    "rule, value, ok",
    [
        (Interval(numbers.Integral, 1, None), 1, True),
        (Interval(numbers.Integral, 1, None), True, False),  # bool is not an int here
        (Interval(numbers.Integral, 1, None), np.int64(3), True),
        (Interval(numbers.Integral, 1, None), 2.0, False),
        (Interval(numbers.Real, 0, 1), 1.0, True),
        (Interval(numbers.Real, 0, 1, closed="left"), 1.0, False),
        (Interval(numbers.Real, 0, None, closed="neither"), 0.0, False),
        (Interval(numbers.Real, None, None), float("inf"), False),
        (Interval(numbers.Real, None, None), float("nan"), False),
        (Interval(numbers.Real, 0, None, allow_none=True), None, True),
        (Interval(numbers.Real, 0, None), None, False),
        (Options(("a", "b")), "a", True),
        (Options(("a", "b")), ["a"], False),
        (Options(("a", "b")), "c", False),
    ],
)
def test_rules_accept_exactly_their_values(rule, value, ok):
    assert rule.accepts(value) is ok


def test_rule_descriptions():
    assert Interval(numbers.Integral, 1, None).describe() == "an int in [1, inf)"
    assert Interval(numbers.Real, 0, 1).describe() == "a float in [0, 1]"
    assert Interval(numbers.Real, 0, None, closed="neither", allow_none=True).describe() == "a float in (0, inf) or None"
    assert Options(("hold", "forget")).describe() == "one of 'hold', 'forget'"


def test_a_gap_beyond_the_float_range_is_refused():
    with pytest.raises(ValueError, match=r"time between two scans must be finite"):
        check_timestamps([-1.7e308, 1.7e308], 2, None)


def test_check_timestamps_gives_elapsed_times():
    np.testing.assert_array_equal(check_timestamps([5.0, 5.5, 8.0], 3, None), [1.0, 0.5, 2.5])
    np.testing.assert_array_equal(check_timestamps([5.0, 5.5], 2, 4.0), [1.0, 0.5])


# ----------------------------------------------------------- property
bad_value = st.sampled_from([np.nan, np.inf, -np.inf])


@st.composite
def bad_batches(draw):
    n = draw(st.integers(1, 6))
    d = draw(st.sampled_from([N_FEATURES, N_FEATURES, 1, N_FEATURES + 2]))
    X = np.random.default_rng(draw(st.integers(0, 99))).uniform(size=(n, d))
    if d == N_FEATURES:  # right shape: poison one entry
        X[draw(st.integers(0, n - 1)), draw(st.integers(0, d - 1))] = draw(bad_value)
    return X


@settings(max_examples=40, deadline=None)
@given(bad_batches(), st.sampled_from(["partial_fit", "stream", "novelty", "predict"]),
       st.booleans())
def test_rejected_input_leaves_state_unchanged(X, method, one_at_a_time):
    det = fitted()
    before = snapshot(det)
    with pytest.raises(ValueError):
        if one_at_a_time:
            for x in X:  # the first bad or misshapen scan is refused
                det.score_learn_one(x) if method in ("partial_fit", "stream") else det.score_one(x)
                before = snapshot(det)  # a good scan may be learned before the bad one
        else:
            call(det, method, X)
    assert_equal_deep(before, snapshot(det))


# ------------------------------------------------------------ init_range
@pytest.mark.parametrize("value, accepted", [
    ((0.0, 1.0), True), ([-2, 3], True), ((np.float32(0.5), 2), True),
    ((1.0, 0.0), False), ((0.5, 0.5), False), ((True, 2.0), False), ((0.0, True), False), ((False, True), False),
    ((0.0, float("inf")), False), ((float("nan"), 1.0), False), ((0.0,), False), ((0.0, 1.0, 2.0), False),
    ("ab", False), (None, False), ((0.0, "1"), False),
])
def test_the_bounds_rule(value, accepted):
    assert Bounds().accepts(value) is accepted


INIT_RANGE = [name for name in clusterers.names() if "init_range" in (clusterers.parameters(name) or [])]


def test_every_builtin_clusterer_with_an_initial_range_is_checked():
    assert {"som", "gng", "gwr", "online-kmeans"} <= set(INIT_RANGE)


@pytest.mark.parametrize("name", INIT_RANGE)
@pytest.mark.parametrize("bad", [(False, 1.0), (0.0, True), (1.0, 0.0), (0.0, float("inf"))])
def test_every_clusterers_initial_range_is_one_check_refusing_booleans(name, bad):
    net = clusterers.make(name, init_range=bad, init="uniform")
    with pytest.raises(ValueError, match=rf"^The 'init_range' parameter of {type(net).__name__} must be a pair "
                                         r"\(low, high\) of finite floats with low < high\. Got "):
        net.initialize(np.zeros((4, 2)), random_state=0)
    assert not hasattr(net, "weights_")

