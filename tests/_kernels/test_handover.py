"""While the pair's driver compiles, the reference learns; the driver takes over mid-stream."""

from __future__ import annotations

import numpy as np
import pytest

import novelty
from novelty import _kernels
from novelty._kernels import handover
from novelty._kernels.engine import CompiledEngine, driver_of
from novelty._kernels.reference import ReferenceEngine

from .kernel_helpers import assert_same_filter, corridor, reference_only

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


def test_learning_hands_over_to_the_kernel_mid_stream(monkeypatch):
    """Three blocks by the reference while "compiling", the rest by the driver once it is
    "ready": the same novelty and state as the reference alone."""
    monkeypatch.setattr(handover, "BLOCK", 100)
    X = corridor(1000)
    det = novelty.make("hsom").fit(X[:1])
    driver = driver_of(det.clusterer_, det.synapse_)
    module = driver.wait()
    calls = []
    reference = ReferenceEngine.learn

    def reference_blocks(engine, X, dt, stimulus, distances=None):
        calls.append(len(X))
        if len(calls) == 3:
            monkeypatch.setattr(driver, "module", module)  # "compiled" after 3 blocks
        return reference(engine, X, dt, stimulus, distances)

    monkeypatch.setattr(driver, "module", None)  # "compiling"
    monkeypatch.setattr(ReferenceEngine, "learn", reference_blocks)
    vars(det).pop("_engine", None)  # an engine chosen now, while "compiling"
    got = det.stream(X)
    assert calls == [100, 100, 100]
    engine = det._engine
    assert type(engine) is CompiledEngine and engine.driving  # handed over
    assert not engine.holds()  # the driver it waited for is ready: another engine is chosen
    monkeypatch.undo()
    with reference_only():
        ref = novelty.make("hsom").fit(X[:1])
        expected = ref.stream(X)
    np.testing.assert_array_equal(got, expected)
    assert_same_filter(det, ref)
