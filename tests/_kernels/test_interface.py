"""The engine interface: one freshness check, by counts of changes, for both engines."""

from __future__ import annotations

import contextlib
import copy
import pickle

import numpy as np
import pytest

import novelty
from novelty._component import StateError
from novelty._kernels import reference_loops
from novelty._kernels.choice import engine_of

from .kernel_helpers import corridor


@pytest.mark.parametrize("reference", [False, True])
def test_an_engine_holds_the_parts_until_one_is_set(reference):
    with reference_loops() if reference else contextlib.nullcontext():
        det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
        engine = engine_of(det)
        det.stream(corridor(10, n_features=4, seed=1))  # its own writes, taken as seen
        assert engine.holds() and engine_of(det) is engine
        det.synapse_.tau_winner = 5.0
        assert not engine.holds()
        assert engine_of(det) is not engine


def test_fresh_also_watches_what_the_owner_gave():
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
    engine = engine_of(det)
    assert engine.holds() and not engine.fresh()  # nothing confirmed by the owner yet
    engine.watch(det, det.synapse)
    assert engine.fresh()
    det.threshold = 0.3  # the owner: fresh no longer, but the engine still holds the parts
    assert engine.holds() and not engine.fresh()
    engine.watch(det, det.synapse)
    det.synapse.alpha = 1.2  # a template the owner watches
    assert engine.holds() and not engine.fresh()


def test_a_copy_or_a_pickle_makes_its_own_engine():
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
    engine_of(det)
    assert copy.deepcopy(det)._engine is None
    assert pickle.loads(pickle.dumps(det))._engine is None


@pytest.mark.parametrize("reference", [False, True])
def test_calibrating_keeps_the_engine_and_learns_as_a_new_engine_would(reference):
    # GWR's "auto" radius calibrates one scan at a time: the engine takes the fitted threshold
    # it sets in place, and learns what engines chosen anew after each scan learned
    X = corridor(260)
    with reference_loops() if reference else contextlib.nullcontext():
        kept = novelty.make("gwr-novelty").fit(X[:2])
        engine = engine_of(kept)
        kept_novelty = kept.partial_fit(X[2:]).stream(X[:20])
        assert engine_of(kept) is engine and kept._calibration.full
        anew = novelty.make("gwr-novelty").fit(X[:2])
        built = []
        with pytest.MonkeyPatch.context() as mp:  # every calibrating scan seen as a change
            mp.setattr(type(engine), "take_parameters", lambda self: built.append(1) or False)
            anew_novelty = anew.partial_fit(X[2:]).stream(X[:20])
        assert len(built) > 100
        np.testing.assert_array_equal(kept_novelty, anew_novelty)
        assert kept.clusterer_.activity_threshold_ == anew.clusterer_.activity_threshold_
        np.testing.assert_array_equal(kept.clusterer_.weights_, anew.clusterer_.weights_)


def test_a_calibrate_that_sets_more_than_fitted_parameters_has_the_state_checked():
    det = novelty.make("gwr-novelty").fit(corridor(5))
    engine = engine_of(det)
    clusterer = det.clusterer_
    # set in its __dict__: an attribute set as usual would count as a change of its own
    vars(clusterer)["calibrate"] = lambda scale: setattr(clusterer, "weights_", np.zeros((2, 99)))
    assert engine.holds()
    engine.calibrate(0.5)
    assert not engine.holds()
    with pytest.raises(StateError, match=r"weights_ has shape \(2, 99\)"):
        det.stream(corridor(3))


def test_a_calibrated_threshold_that_is_not_a_finite_number_is_not_taken_in_place():
    det = novelty.make("gwr-novelty").fit(corridor(5))
    engine = engine_of(det)
    clusterer = det.clusterer_
    vars(clusterer)["calibrate"] = lambda scale: setattr(clusterer, "activity_threshold_", float("nan"))
    assert engine.holds()
    engine.calibrate(0.5)
    assert not engine.holds()  # the next call chooses another engine, after the full check


def test_a_calibrate_that_sets_a_nested_part_has_the_state_checked():
    det = novelty.make("gwr-novelty").fit(corridor(5))
    engine = engine_of(det)
    firing = det.clusterer_.firing_
    vars(det.clusterer_)["calibrate"] = lambda scale: setattr(firing, "efficacy_", firing.efficacy_[:1].copy())
    assert engine.holds()
    engine.calibrate(0.5)
    assert not engine.holds()
    with pytest.raises(StateError, match="efficacy_ has shape"):
        det.stream(corridor(3))
