"""Bad scans and batches: a clear ValueError, and the model exactly as it was."""

import warnings

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from sklearn.exceptions import NotFittedError

import novelty
from novelty._validation import MAX_SCAN_NORM, check_batch

from .model_state import N_FEATURES, assert_equal_deep, fitted, snapshot


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
    "strings": ([["a", "b", "c", "d"]], r"expects X as a 2-D array of numbers; got the string 'a' in row 0, "
                                        r"column 0"),
    "a numeric string": ([row(0.5), row("0.3")], r"got the string '0.3' in row 1, column 1; convert text"),
    "an array of numeric strings": (np.array([row(0.5)], dtype=str), r"got the string '0.5' in row 0, column 0"),
    "bytes in an object array": (np.array([row(b"0.3")], dtype=object), r"got the string b'0.3' in row 0, column 1"),
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
    "strings": (["a", "b", "c", "d"], r"expects one scan of numbers; got the string 'a' as value 0"),
    "a numeric string": (row("0.3"), r"expects one scan of numbers; got the string '0.3' as value 1; convert text"),
    "an array of numeric strings": (np.array(row(0.5), dtype=str), r"got the string '0.5' as value 0"),
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
    with pytest.raises(ValueError, match=message) as raised:
        call(det, method, X)
    assert not type(raised.value).__name__.startswith("_")  # the traceback names a class a user knows
    assert_equal_deep(before, snapshot(det))


@pytest.mark.parametrize("method", ONE_METHODS)
@pytest.mark.parametrize("case", list(BAD_SCANS))
def test_bad_scan_is_refused_and_changes_nothing(method, case):
    x, message = BAD_SCANS[case]
    det = fitted()
    before = snapshot(det)
    with pytest.raises(ValueError, match=message) as raised:
        getattr(det, method)(x)
    assert not type(raised.value).__name__.startswith("_")  # the traceback names a class a user knows
    assert_equal_deep(before, snapshot(det))


@pytest.mark.parametrize("method", ONE_METHODS)
def test_a_string_in_a_dict_scan_is_refused_by_its_key(method):
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    det.learn_one({"a": 0.1, "b": 0.2})
    before = snapshot(det)
    with pytest.raises(ValueError, match=r"HabituatingFilter expects one scan of numbers; got the string '0.3' "
                                         r"as the value of key 'b'; convert text to numbers first"):
        getattr(det, method)({"a": 0.1, "b": "0.3"})
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


# --------------------------------------------- plain float arrays, taken as they are
def _as_check_array(X):
    from sklearn.utils import check_array

    return check_array(X, dtype=np.float64, order="C", ensure_all_finite=False)


@pytest.mark.parametrize("make", [
    lambda X: X,
    np.asfortranarray,
    lambda X: np.repeat(X, 2, axis=1)[:, ::2],  # strided
    lambda X: X.astype(np.float32),
    lambda X: np.asfortranarray(X.astype(np.float32)),
    lambda X: X.astype(">f8"),  # not the machine's byte order: the general path
    lambda X: X.tolist(),
])
def test_a_batch_is_what_scikit_learn_would_make_of_it(make):
    X = make(np.random.default_rng(3).uniform(-2, 2, size=(7, N_FEATURES)))
    det = fitted()
    got = check_batch(X, det, N_FEATURES)
    assert got.dtype == np.float64 and got.flags.c_contiguous
    np.testing.assert_array_equal(got, _as_check_array(X))


def test_a_plain_batch_is_not_copied_and_a_read_only_one_is_not_written():
    X = np.random.default_rng(4).uniform(size=(5, N_FEATURES))
    assert check_batch(X, fitted()) is X
    X.flags.writeable = False
    det = fitted()
    det.partial_fit(X)
    assert check_batch(X, det) is X


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.999_998, 1.000_002), min_size=1, max_size=5), st.integers(0, 3))
def test_scans_near_the_norm_bound_are_refused_exactly_when_a_row_is_above_it(scales, column):
    # rows of norms about the bound: one sum over the batch may clear it, but the
    # verdict is the row by row one
    X = np.zeros((len(scales), N_FEATURES))
    X[:, column] = np.array(scales) * MAX_SCAN_NORM
    X[:, (column + 1) % N_FEATURES] = 1e90
    above = np.flatnonzero(~(np.einsum("ij,ij->i", X, X) <= MAX_SCAN_NORM**2))
    det = fitted()
    if above.size:
        with pytest.raises(ValueError, match=rf"norm above 1e\+100 \(first in row {above[0]}\)"):
            check_batch(X, det, N_FEATURES)
    else:
        assert check_batch(X, det, N_FEATURES) is X


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_plain_batch_with_a_bad_value_names_its_first_row(dtype, bad):
    X = np.full((6, N_FEATURES), 0.5, dtype=dtype)
    X[4, 2] = bad
    X[5, 0] = bad
    with pytest.raises(ValueError, match=r"NaN or infinity \(first in row 4\)"):
        check_batch(X, fitted(), N_FEATURES)


def test_checking_norms_warns_of_nothing():
    # many rows of norms just under the bound overflow the batch's sum, and values
    # beyond the float range overflow a row's: an answer of the check, not a warning
    det = fitted()
    near = np.zeros((5000, N_FEATURES))
    near[:, 0] = 0.9 * MAX_SCAN_NORM
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_batch(near, det, N_FEATURES) is near
        huge = np.full((3, N_FEATURES), 1e200)
        with pytest.raises(ValueError, match=r"norm above 1e\+100 \(first in row 0\)"):
            check_batch(huge, det, N_FEATURES)
        with pytest.raises(ValueError, match=r"norm above 1e\+100"):
            det.score_one(np.full(N_FEATURES, 1e200))


# ------------------------------------------------------------------ cleared
_VALUES = st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=64),
                    st.sampled_from([0.0, 1e99, 1e100, 1.0000001e100, 7e99, 1e150, 1e154, 1e155, 1e300]))


_LAYOUTS = ["plain", "transposed", "long", "big-endian", "float32", "read-only"]


@given(st.lists(st.lists(_VALUES, min_size=3, max_size=3), min_size=1, max_size=6), st.sampled_from(_LAYOUTS))
@example([[0.0, 0.0, 1.8446743523953738e+19]], "float32")  # its square overflows float32: summed in float64
@settings(max_examples=300, deadline=None)
def test_an_array_cleared_is_finite_and_within_the_norm_bound_row_by_row(rows, layout):
    """``cleared`` is the fast half of the state's value checks: what it clears, the exact
    checks (finite, each row's norm within MAX_SCAN_NORM) would pass; a strided view is
    summed as its values are; every layout (BLAS's ddot for a short contiguous float64
    array, einsum for the others and for more than 4096 values) answers overflow without a
    warning."""
    from novelty._validation.scans import cleared

    with np.errstate(over="ignore", invalid="ignore"):
        a = np.array(rows, dtype=np.float32 if layout == "float32" else np.float64)
    if layout == "long":
        a = np.tile(a, (700, 1))  # beyond 4096 values
    view = {"transposed": lambda: np.ascontiguousarray(a.T).T,  # the compiled engine's weights_
            "big-endian": lambda: a.astype(a.dtype.newbyteorder(">"))}.get(layout, lambda: a)()
    if layout == "read-only":
        view.setflags(write=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # overflow is an answer here, never a warning
        verdict = bool(cleared(view))
    with np.errstate(over="ignore", invalid="ignore"):
        wide = a.astype(np.longdouble)
        norms = np.sqrt(np.einsum("ij,ij->i", wide, wide))
    if verdict:
        assert np.isfinite(a).all() and norms.max() <= MAX_SCAN_NORM
    if np.isfinite(a).all() and np.abs(a).max() <= 1e90:  # far inside: always cleared
        assert verdict


def test_only_float_arrays_are_cleared():
    from novelty._validation.scans import cleared

    wrapping = np.full(4, 2**32, dtype=np.int64)  # its squares wrap around to 0 in int64
    assert np.dot(wrapping, wrapping) == 0
    assert not cleared(wrapping) and not cleared(np.zeros(3, dtype=bool))
    assert cleared(np.zeros(3)) and cleared(np.ones((2, 2, 2)))
    assert cleared(np.empty((0, 3))) and cleared(np.empty(0))  # nothing beyond the bound
