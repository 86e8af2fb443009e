"""Which engine a filter gets, and why: decided in one place (novelty._kernels.choice)."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

import novelty
from novelty import _kernels, registry
from novelty._kernels.choice import why_not_learning
from novelty._kernels.engine import CompiledEngine
from novelty._kernels.reference import ReferenceEngine
from novelty.clusterers.gwr import GrowWhenRequired
from novelty.filter import HabituatingFilter

from tests.damaged import damaging

from .kernel_helpers import assert_same_filter, corridor, reference_only

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")

UNDECLARED = [(r, n) for r in (registry.clusterers, registry.synapses) for n in r.names()
              if "_kernel" not in vars(type(r.make(n)))]


@pytest.mark.parametrize("registry_, name", UNDECLARED or [pytest.param(None, None, marks=pytest.mark.skip(
    reason="no registered component without compiled steps (the example plugin is not installed)"))])
def test_a_registered_component_without_compiled_steps_runs_the_reference(registry_, name):
    X = corridor(30)
    part = "clusterer" if registry_ is registry.clusterers else "synapse"
    det = HabituatingFilter(**{part: name}).fit(X)
    assert det.compiled_.startswith("reference (")
    assert why_not_learning(det.clusterer_, det.synapse_) is not None


def test_the_reasons_and_the_engines(monkeypatch):
    """compiled_ says which loop learns and why; the engine is a ReferenceEngine when neither
    learning nor scoring compiles, else a CompiledEngine told which halves compile."""
    root = Path(__file__).resolve().parents[2]
    monkeypatch.syspath_prepend(str(root / "examples" / "novelty-plugin-example" / "src"))
    from novelty_plugin_example import LeaderClusterer  # declares no compiled steps

    class MySOM(novelty.SOM):  # may change the arithmetic: not compiled unless it says so
        pass

    X = corridor(50)
    hsom = novelty.make("hsom").fit(X)
    assert _kernels.wait(hsom.clusterer_, hsom.synapse_) is not None and _kernels.wait() is not None
    assert hsom.compiled_ == "compiled" and type(hsom._current_engine()) is CompiledEngine
    for clusterer in (MySOM(n_rows=2, n_columns=2), LeaderClusterer()):
        det = HabituatingFilter(clusterer=clusterer).fit(X)
        assert det.compiled_ == f"reference ({type(clusterer).__name__} declares no compiled steps)"
        assert type(det._current_engine()) is ReferenceEngine  # and neither declares nearest-unit
    gwr = HabituatingFilter(clusterer=GrowWhenRequired(firing="wang-hsu")).fit(X)
    assert gwr.compiled_ == "reference (GrowWhenRequired's parts declare other steps)"
    engine = gwr._current_engine()  # learning by the reference, scoring compiled (GWR's is nearest-unit)
    assert type(engine) is CompiledEngine and engine._kernels is not None and not engine.driving
    with reference_only():
        det = novelty.make("hsom").fit(X)
        assert det.compiled_ == "reference (NOVELTY_NO_KERNELS)" and type(det._current_engine()) is ReferenceEngine
    # the variable is read on every call: an engine chosen under it is not kept after
    assert type(det._current_engine()) is CompiledEngine


def test_a_layout_the_driver_does_not_take_is_copied():
    X = corridor(50)
    hsom = novelty.make("hsom").fit(X)
    with damaging(hsom):
        hsom.clusterer_.weights_ = np.asfortranarray(hsom.clusterer_.weights_)
    got = hsom.stream(X)
    ref = novelty.make("hsom").fit(X)
    with reference_only():
        np.testing.assert_array_equal(got, ref.stream(X))
    assert_same_filter(hsom, ref)


def test_the_filter_holds_its_engine_dropped_by_set_params_and_load(tmp_path):
    """One engine per fitted filter, kept between calls while it holds the parts; set_params
    drops it, a loaded model and a copy make their own."""
    X = corridor(60)
    det = novelty.make("hsom").fit(X[:20])
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None and _kernels.wait() is not None
    engine = det._current_engine()
    assert engine.clusterer is det.clusterer_ and engine.synapse is det.synapse_
    det.stream(X[20:30])
    det.score_learn_one(X[30])
    assert det._engine is engine
    det.set_params(threshold=0.4)
    assert "_engine" not in vars(det)
    det.score_learn_one(X[30])
    assert det._engine is not engine and det._engine.clusterer is det.clusterer_
    copied = copy.deepcopy(det)  # holds what its own engine is made from (test_interface)
    assert copied._current_engine() is not det._engine and copied._engine.clusterer is copied.clusterer_
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert "_engine" not in vars(loaded)
    np.testing.assert_array_equal(loaded.stream(X[31:]), det.stream(X[31:]))
    assert loaded._engine.clusterer is loaded.clusterer_


def test_another_engine_once_a_part_is_replaced_or_set():
    X = corridor(60)
    det = novelty.make("hsom").fit(X[:20])
    engine = det._current_engine()
    assert det._current_engine() is engine
    with damaging(det):
        det.clusterer_.learning_rate = 0.5  # a parameter set on a fitted part: read again
    assert det._current_engine() is not engine
    engine = det._current_engine()
    det.synapse_ = copy.deepcopy(det.synapse_)
    assert det._current_engine() is not engine and det._engine.synapse is det.synapse_
