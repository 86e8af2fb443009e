"""The kernels' tricks on numba's internals: their self-check passes here, and a failing one turns
them off with a warning and the same results (novelty._kernels.tricks)."""

from __future__ import annotations

import numpy as np
import pytest

import novelty
from novelty import _kernels
from novelty._kernels import children, drivers, tricks
from novelty._kernels.engine import driver_of

from .kernel_helpers import corridor, reference_only

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


@pytest.mark.slow
def test_the_self_check_passes_with_this_numba():
    assert children.run_self_check() == (True, "")


@pytest.fixture
def unchecked(tmp_path, monkeypatch):
    """A process that has not decided on the tricks, with an empty folder of drivers."""
    monkeypatch.setenv("NOVELTY_KERNEL_DIR", str(tmp_path))
    monkeypatch.delenv(tricks.VARIABLE, raising=False)
    monkeypatch.setattr(tricks, "_verdict", None)
    monkeypatch.setattr(drivers, "_drivers", {})
    return tmp_path


@pytest.mark.slow
def test_a_self_check_that_crashes_turns_the_tricks_off_with_the_same_results(unchecked, monkeypatch):
    """As if a numba release made the uncounted aliases a use-after-free: the check's child dies."""
    monkeypatch.setattr(children, "_PROBE", "import os; os.abort()")
    X = corridor(300)
    with pytest.warns(RuntimeWarning, match=r"failed their self-check \(the check crashed"):
        det = novelty.make("hsom").fit(X[:1])
        assert _kernels.wait(det.clusterer_, det.synapse_) is not None
    assert tricks.known() is False and not tricks.enabled()
    compiled = driver_of(det.clusterer_, det.synapse_)
    with open(compiled.file, encoding="utf-8") as f:
        assert "tricks on numba's internals: not used (plain)" in f.read()
    assert len(list(unchecked.glob("tricks-*.failed"))) == 1  # kept for later processes
    got = det.stream(X)
    with reference_only():
        ref = novelty.make("hsom").fit(X[:1])
        expected = ref.stream(X)
    np.testing.assert_array_equal(got, expected)


def test_a_failed_verdict_is_read_by_a_later_process_and_reported(unchecked, monkeypatch):
    tricks.write(str(unchecked), drivers._package_digest(), False, "move_four: other values")
    monkeypatch.setattr(children, "_PROBE", "raise SystemExit('the check must not run again')")
    with pytest.warns(RuntimeWarning, match="as found by an earlier process"):
        assert drivers._tricks_decided(settle=False)
    assert tricks.known() is False
