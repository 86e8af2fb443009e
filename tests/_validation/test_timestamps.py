"""Bad timestamps: a clear ValueError, and the model exactly as it was; elapsed times by hand."""

import numpy as np
import pytest

from novelty._validation import check_timestamps

from .model_state import N_FEATURES, assert_equal_deep, fitted, snapshot


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


def test_a_gap_beyond_the_float_range_is_refused():
    with pytest.raises(ValueError, match=r"time between two scans must be finite"):
        check_timestamps([-1.7e308, 1.7e308], 2, None)


def test_check_timestamps_gives_elapsed_times():
    np.testing.assert_array_equal(check_timestamps([5.0, 5.5, 8.0], 3, None), [1.0, 0.5, 2.5])
    np.testing.assert_array_equal(check_timestamps([5.0, 5.5], 2, 4.0), [1.0, 0.5])
