"""The reference engine: the readable loop, on the parts' own arrays."""

from __future__ import annotations

import contextlib
import copy

import numpy as np

import novelty
from novelty._kernels import reference_loops
from novelty._kernels.reference import ReferenceEngine, learn_stream
from novelty.match_scale import ScaleCalibration

from tests.damaged import damaging

from .kernel_helpers import corridor


def test_the_loop_by_hand():
    """One unit of a 1 x 1 map, a scan at distance 2 twice: the novelty is the efficacy before
    each scan (1, then the Euler step 1 - 1.05 / 3.33 of the way to 1 - 1 / 1.05), the unit moves
    a quarter of the way each time."""
    det = novelty.make("hsom", n_rows=1, n_columns=1).fit(np.zeros((1, 1)))
    c, s = det.clusterer_, det.synapse_
    with damaging(det):  # the loop writes the parts, as their engine does
        c.weights_[:] = 0.0
        s.efficacy_[:] = 1.0
        distances = np.empty(2)
        got = learn_stream(c, s, np.array([[2.0], [2.0]]), np.ones(2), 1.0, distances)
    rest = 1 - 1 / 1.05
    y1 = 1.0 + (1.05 / 3.33) * (rest - 1.0)
    np.testing.assert_allclose(got, [1.0, y1], rtol=1e-15)
    np.testing.assert_array_equal(distances, [4.0, 1.5**2])  # 0 -> 0.5 after the first
    assert c.weights_[0, 0] == 0.875


def test_scans_the_single_scan_call_leaves_to_the_general_path():
    with reference_loops():
        det = novelty.make("hsom", n_rows=2, n_columns=2).fit(corridor(20, n_features=3))
        engine = det._current_engine()
        assert isinstance(engine, ReferenceEngine)
        before = det.clusterer_.weights_.copy()
        for x in (np.ones(4), np.array([0.0, np.nan, 0.0]), np.full(3, 1e300)):
            assert not engine.learn_one(x, 1.0) and not engine.score_one(x)
        np.testing.assert_array_equal(det.clusterer_.weights_, before)  # nothing learned
        assert engine.learn_one(np.full(3, 0.5), 1.0) and engine.score_one(np.full(3, 0.5))


def test_a_read_only_array_is_copied_before_the_loop_writes_into_it():
    with reference_loops():
        det = novelty.make("hsom", n_rows=2, n_columns=2).fit(corridor(20, n_features=3))
        frozen = det.synapse_.efficacy_.copy()
        frozen.setflags(write=False)
        values = frozen.copy()
        with damaging(det):
            det.synapse_.efficacy_ = frozen
        det.stream(corridor(5, n_features=3, seed=1))
        assert det.synapse_.efficacy_ is not frozen and not frozen.flags.writeable
        np.testing.assert_array_equal(frozen, values)  # the caller's array, never written


def test_learn_calibrating_gives_each_row_the_scale_before_it():
    """Scans 0, 2, 3, 7 into a calibration of four: no scale before two distinct scans, then the
    median nearest-distinct distance of those before (2; then 2, 1, 1: 1; then 2, 1, 1, 4: 1.5);
    the fifth row learned after it is full; the efficacies those of learning the rows in one call."""
    X = np.array([[0.0], [2.0], [3.0], [7.0], [1.0]])
    for kernels in (False, True):
        with reference_loops() if not kernels else contextlib.nullcontext():
            det = novelty.make("hsom", n_rows=1, n_columns=2, match_scale=1.0).fit(X[:1])
            twin = copy.deepcopy(det)
            calibration = ScaleCalibration(np.empty((0, 1)), 4, 0.5)
            distances = np.empty(5)
            efficacy, scales, scale = det._current_engine().learn_calibrating(
                X, np.ones(5), 1.0, calibration, None, distances)
            expected = np.empty(5)
            np.testing.assert_array_equal(efficacy, twin._current_engine().learn(X, np.ones(5), 1.0, expected))
        np.testing.assert_array_equal(distances, expected)
        assert scales == [None, None, 2.0, 1.0] and scale == 1.5 and calibration.full
