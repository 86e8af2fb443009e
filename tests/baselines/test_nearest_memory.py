"""The perfect-memory baseline: hand-computed distances, exclusion, bounded memory, files."""

import math

import numpy as np
import pytest

import novelty
from novelty.baselines.nearest_memory import NearestMemory
from novelty.registry import build

LINE = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0], [6.0, 0.0], [10.0, 0.0]])


def test_registered_by_name():
    assert isinstance(build("detector", "nearest-memory"), NearestMemory)


def test_raw_novelty_is_the_distance_to_the_nearest_scan():
    det = NearestMemory().fit(LINE)
    assert det.raw_novelty([[2.0, 0.0], [3.0, 4.0], [10.0, 0.0]]).tolist() == [1.0, 4.0, 0.0]


def test_stream_scores_each_scan_before_learning_it():
    det = NearestMemory()
    det.stream(LINE)
    # raw distances before learning: inf, 1, 2, 3, 4; the first two have no reference to compare with
    ref = det.reference_.tolist()
    assert ref == [1.0, 2.0, 3.0, 4.0]


def test_exclusion_and_bounded_memory_by_hand():
    det = NearestMemory(exclude_recent=1, max_memory=3)
    out = det.stream(LINE)
    # scan 2: eligible {0} -> raw 3, empty reference -> 1.0; scan 3: eligible {0, 1} -> raw 5,
    # reference [3] (F = 1/2, lam = 1): 1 - e^-2 / 2; memory then [1, 3, 6]; scan 4: eligible {1, 3}
    # -> raw 7, reference [3, 5] (F = 2/3, lam = 1): 1 - e^-2 / 3
    expected = [1.0, 1.0, 1.0, 1 - math.exp(-2) / 2, 1 - math.exp(-2) / 3]
    np.testing.assert_allclose(out, expected, rtol=1e-12)
    assert det.memory_[:, 0].tolist() == [3.0, 6.0, 10.0]
    assert det.raw_novelty([[2.0, 0.0]]).tolist() == [1.0]   # (3, 0); (10, 0) is excluded


def test_nothing_eligible_is_fully_novel():
    det = NearestMemory(exclude_recent=5).fit(LINE[:2])
    assert det.raw_novelty([[0.0, 0.0]]).tolist() == [math.inf]
    assert det.novelty([[0.0, 0.0]]).tolist() == [1.0]


def test_batch_scoring_matches_one_scan_at_a_time():
    rng = np.random.default_rng(0)
    det = NearestMemory(exclude_recent=2).fit(rng.random((60, 5)))
    X = rng.random((25, 5))
    one = [det.score_one(x) for x in X]
    np.testing.assert_allclose(det.novelty(X), one, rtol=0, atol=0)


def test_fit_equals_stream_and_learn_one():
    rng = np.random.default_rng(1)
    X = rng.random((40, 3))
    fitted = NearestMemory(max_memory=25).fit(X)
    streamed = NearestMemory(max_memory=25)
    streamed.stream(X[:10])
    for x in X[10:]:
        streamed.learn_one(x)
    np.testing.assert_array_equal(fitted.memory_, streamed.memory_)
    np.testing.assert_array_equal(fitted.memory_, X[-25:])


def test_saved_and_loaded_it_goes_on_as_before(tmp_path):
    rng = np.random.default_rng(2)
    X, later = rng.random((30, 4)), rng.random((10, 4))
    det = NearestMemory(exclude_recent=2, max_memory=20)
    det.stream(X)
    det.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    np.testing.assert_array_equal(back.memory_, det.memory_)
    np.testing.assert_array_equal(back.stream(later), det.stream(later))


@pytest.mark.parametrize("params, message", [
    ({"exclude_recent": -1}, "exclude_recent"),
    ({"max_memory": 0}, "max_memory"),
    ({"exclude_recent": 3, "max_memory": 3}, "must exceed exclude_recent"),
])
def test_bad_parameters_are_refused(params, message):
    with pytest.raises(ValueError, match=message):
        NearestMemory(**params).fit(LINE)
