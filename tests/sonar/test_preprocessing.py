import numpy as np
import pytest

from novelty.sonar import bin_by_distance, preprocess


def test_threshold_normalise_invert_on_hand_made_readings():
    readings = np.array([[0.15, 1.0, 2.0, 3.0, 3.99, 4.0, 5.2, 6.5]])
    out = preprocess(readings)
    assert out[0] == pytest.approx([0.9625, 0.75, 0.5, 0.25, 0.0025, 0.0, 0.0, 0.0])
    assert preprocess([2.5], threshold=5.0)[0] == pytest.approx(0.5)


def test_preprocess_rejects_nan_and_bad_threshold():
    with pytest.raises(ValueError, match="NaN"):
        preprocess([np.nan])
    with pytest.raises(ValueError, match="threshold"):
        preprocess([1.0], threshold=0.0)


def test_bin_by_distance_averages_each_10_cm():
    values = np.array([[1.0, 0.0], [0.0, 0.0], [0.5, 1.0], [0.25, 1.0], [0.75, 0.5]])
    travelled = np.array([0.01, 0.06, 0.12, 0.18, 0.25])
    means, member = bin_by_distance(values, travelled, 0.1)
    assert member.tolist() == [0, 0, 1, 1, 2]
    assert means.tolist() == [[0.5, 0.0], [0.375, 1.0], [0.75, 0.5]]


def test_empty_bin_takes_the_nearest_ring():
    values = np.array([[1.0], [0.0]])
    means, _ = bin_by_distance(values, np.array([0.05, 0.29]), 0.1, n_bins=3)
    # bin 1 (0.1-0.2, centre 0.15) is empty: the ring at 0.05 is nearer than the one at 0.29
    assert means.ravel().tolist() == [1.0, 1.0, 0.0]


def test_bin_by_distance_validates():
    with pytest.raises(ValueError, match="non-decreasing"):
        bin_by_distance([[1.0], [2.0]], [0.2, 0.1])
