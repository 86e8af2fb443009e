"""The map's compiled loop against its numpy reference, with every registered synapse; its state and its bounds."""

import contextlib
import copy
import pickle

import numpy as np
import pytest

from novelty import _kernels
from novelty.maps import HabituatingMap
from novelty.maps.map_engine import wait
from novelty.io.scans.points import example_rows
from novelty.maps.tiles import GridFullWarning
from novelty.registry import synapses
from tests.damaged import damaging


def drive(n=150, shift=0.0, seed=3):
    """Rows of the example corridor, moved ``shift`` m along it."""
    X = example_rows(seed=seed, n=n)
    X[:, [0] + list(range(11, 19))] += shift
    return X


def both(params, X, timestamps=None):
    """The map learned and scored compiled, then by the reference: (novelty learning, novelty after, map)."""
    fast = HabituatingMap.from_params(**params).fit(X[:1], timestamps=None if timestamps is None else timestamps[:1])
    assert wait(fast.clusterer_, fast.synapse_)
    rest = None if timestamps is None else timestamps[1:]
    got = fast.stream(X[1:], timestamps=rest), fast.novelty(X), fast
    assert fast.compiled_ == "compiled"
    with _kernels.reference_loops():
        slow = HabituatingMap.from_params(**params).fit(X[:1], timestamps=None if timestamps is None else timestamps[:1])
        expected = slow.stream(X[1:], timestamps=rest), slow.novelty(X), slow
        assert slow.compiled_ == "reference (NOVELTY_NO_KERNELS)"
    return got, expected


def assert_same_map(a, b):
    for part in ("clusterer_", "synapse_"):
        for name, value in vars(getattr(a, part)).items():
            if name.endswith("_") and not name.startswith("_"):
                np.testing.assert_array_equal(value, getattr(getattr(b, part), name), err_msg=f"{part}.{name}")


@pytest.mark.parametrize("synapse", synapses.names())
@pytest.mark.parametrize("params", [
    {},
    {"others": "forget", "neighbours": True, "tau_neighbour": 5.0, "visit_gap": 3},
    {"arc": 0.2, "evidence_lag": 2, "min_passes": 1, "top": None, "evidence": "hits", "tolerance": 2},
])
def test_the_compiled_loop_is_the_reference_bit_for_bit(synapse, params):
    X = np.vstack([drive(), drive(shift=3.0, seed=5)])
    t = np.cumsum(1.0 + np.random.default_rng(0).integers(0, 3, len(X)) * 0.5)
    (got, got_after, fast), (expected, expected_after, slow) = both({"synapse": synapse, **params}, X, t)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(got_after, expected_after)
    assert_same_map(fast, slow)


def test_scans_pending_from_a_batch_of_longer_rays_are_walked_whole_in_a_batch_of_short_ones():
    # the passes of the last evidence_lag scans count in the next batch: its room is made for them too
    long, short = drive(n=40), drive(n=40, shift=3.0, seed=5)
    short[:, 11:19], short[:, 19:27] = short[:, [0]] + 0.01, short[:, [1]]   # every echo 1 cm ahead of the robot
    params = {"cell_size": 0.05, "arc": "sector", "evidence_lag": 3}
    fast = HabituatingMap.from_params(**params).fit(long)
    assert wait(fast.clusterer_, fast.synapse_)
    fast.stream(long)
    with _kernels.reference_loops():
        slow = HabituatingMap.from_params(**params).fit(long)
        slow.stream(long)
        expected = slow.stream(short)
    assert fast.compiled_ == "compiled"
    np.testing.assert_array_equal(fast.stream(short), expected)
    assert_same_map(fast, slow)


def test_a_long_drive_grows_the_arrays_and_loses_nothing():
    X = np.vstack([drive(n=60, shift=s) for s in np.arange(0.0, 120.0, 6.0)])
    (got, _, fast), (expected, _, slow) = both({"cell_size": 0.05}, X)
    np.testing.assert_array_equal(got, expected)
    assert fast.clusterer_.tiles_.size > 64
    assert_same_map(fast, slow)


def test_a_full_map_reads_cells_beyond_it_as_never_met_in_both_loops():
    X = np.vstack([drive(n=60, shift=s) for s in np.arange(0.0, 60.0, 6.0)])
    with pytest.warns(GridFullWarning, match="max_cells = 2560 cells"):
        (got, _, fast), (expected, _, slow) = both({"max_cells": 2560}, X)
    np.testing.assert_array_equal(got, expected)
    assert fast.clusterer_.tiles_.size == slow.clusterer_.tiles_.size == 10
    assert_same_map(fast, slow)


def test_a_copy_or_a_pickle_of_a_compiled_map_goes_on_as_the_map_it_was():
    X = drive()
    det = HabituatingMap().fit(X[:1])
    wait(det.clusterer_, det.synapse_)
    det.partial_fit(X[1:80])
    assert det.compiled_ == "compiled"
    for other in (copy.deepcopy(det), pickle.loads(pickle.dumps(det))):
        np.testing.assert_array_equal(other.stream(X[80:]), copy.deepcopy(det).stream(X[80:]))


def test_a_state_replaced_behind_the_maps_back_is_read_again_or_refused():
    X = drive()
    det = HabituatingMap().fit(X[:100])
    wait(det.clusterer_, det.synapse_)
    reference = copy.deepcopy(det)
    with damaging(det):  # past the lock, as nothing in the library may (tests.damaged)
        det.clusterer_.passes_ = det.clusterer_.passes_.copy()    # replaced, same values: read again
    np.testing.assert_array_equal(det.stream(X[100:]), reference.stream(X[100:]))
    with damaging(det):
        det.clusterer_.passes_ = det.clusterer_.passes_[:-1]       # a cell short: refused by name
    with pytest.raises(ValueError, match="passes_"):
        det.novelty(X)


@pytest.mark.parametrize("reference", [False, True])
def test_a_fitted_map_s_parts_are_read_only_and_its_own_calls_write_them(reference):
    import novelty

    X = drive()
    with _kernels.reference_loops() if reference else contextlib.nullcontext():
        det = HabituatingMap.from_params().fit(X[:100])  # parts as instances: set_params reaches them
        before = det.novelty(X[100:])
        with pytest.raises(novelty.FittedPartError, match=r"WorldCells\.top cannot be set.*clusterer__top"):
            det.clusterer_.top = 3
        with pytest.raises(novelty.FittedPartError, match=r"StanleySynapse\.efficacy_ cannot be set"):
            det.synapse_.efficacy_ = det.synapse_.efficacy_.copy()
        for part in (det.clusterer_, det.synapse_):
            for name, value in vars(part).items():
                if type(value) is np.ndarray and name.endswith("_") and not name.startswith("_") and value.size:
                    assert not value.flags.writeable, f"{type(part).__name__}.{name}"
                    with pytest.raises(ValueError, match="read-only"):
                        value.flat[0] = 0
        np.testing.assert_array_equal(det.novelty(X[100:]), before)
        det.partial_fit(X[100:120])  # its engine writes them, and reads them again after the map's set_params
        det.set_params(top=3)
        assert det.clusterer_.top == 3
        twin = HabituatingMap.from_params(top=3).fit(X[:100])
        twin.partial_fit(X[100:120])
        np.testing.assert_array_equal(det.novelty(X[120:]), twin.novelty(X[120:]))
        assert not det.synapse_.efficacy_.flags.writeable
