"""The engine interface: one freshness check, by counts of changes, for both engines."""

from __future__ import annotations

import contextlib
import copy
import pickle

import pytest

import novelty
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
