"""Bad timestamps: a clear ValueError, and the model exactly as it was; elapsed times by hand."""

import numpy as np
import pytest

import novelty

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


@pytest.mark.parametrize("t0", [1.7e18, 1_700_000_000_000_000_000, np.int64(1_700_000_000_000_000_000)])
def test_an_epoch_timestamp_first_is_one_step(t0):
    # float64 cannot tell 1.7e18 - 1 from 1.7e18; the first scan is one step whatever its time
    det = novelty.make("hsom")
    scan = np.full(16, 0.5)
    det.learn_one(scan, t=t0)
    assert round(det.score_one(scan), 4) == 0.6997  # the paper's second value
    np.testing.assert_array_equal(check_timestamps([t0, t0], 2, None), [1.0, 0.0])


def test_integer_timestamps_are_subtracted_exactly():
    t = np.array([1_700_000_000_000_000_000, 1_700_000_000_000_000_001, 1_700_000_000_000_000_101])
    np.testing.assert_array_equal(check_timestamps(t, 3, None), [1.0, 1.0, 100.0])
    np.testing.assert_array_equal(check_timestamps(t[1:], 2, int(t[0])), [1.0, 100.0])
    np.testing.assert_array_equal(check_timestamps([-2**63, 2**63 - 1], 2, None), [1.0, 2.0**64])
    with pytest.raises(ValueError, match="must not decrease"):
        check_timestamps(t[:1], 1, int(t[0]) + 1)


def test_integer_timestamps_keep_the_last_time_exact_through_a_file(tmp_path):
    det = novelty.make("hsom", n_rows=2)
    det.partial_fit(np.full((2, 3), 0.5), timestamps=[1_700_000_000_000_000_000, 1_700_000_000_000_000_001])
    assert det.last_time_ == 1_700_000_000_000_000_001 and isinstance(det.last_time_, int)
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert loaded.last_time_ == 1_700_000_000_000_000_001
    a, b = det.score_learn_one(np.full(3, 0.5), t=1_700_000_000_000_000_003), \
        loaded.score_learn_one(np.full(3, 0.5), t=1_700_000_000_000_000_003)
    assert a == b
    np.testing.assert_array_equal(det.synapse_.efficacy_, loaded.synapse_.efficacy_)
