"""The drivers compose a plugin's steps: the guide's new synapse (``fading.py``) runs compiled
inside hsom's map, as the reference does."""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import novelty
from novelty import _kernels

from .kernel_helpers import assert_same_filter, corridor, reference_only

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")

EXTENDING = Path(__file__).resolve().parents[2] / "docs" / "guide" / "extending.md"


def test_the_guide_synapse_learns_compiled_as_the_reference(tmp_path, monkeypatch):
    block = next(b for b in re.findall(r"```python\n(.*?)```", EXTENDING.read_text(encoding="utf-8"),
                                       flags=re.S) if b.startswith("# fading.py\n"))
    (tmp_path / "fading.py").write_text(block, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "fading", raising=False)
    Fading = importlib.import_module("fading").Fading
    X = corridor(400)
    fast = novelty.HabituatingFilter(clusterer="som", synapse=Fading()).fit(X[:1])
    assert fast.compiled_ == "compiled"
    assert _kernels.wait(fast.clusterer_, fast.synapse_) is not None  # the pair's driver
    got = fast.stream(X[1:])
    with reference_only():
        slow = novelty.HabituatingFilter(clusterer="som", synapse=Fading()).fit(X[:1])
        assert slow.compiled_ == "reference (NOVELTY_NO_KERNELS)"
        expected = slow.stream(X[1:])
    np.testing.assert_array_equal(got, expected)
    assert_same_filter(fast, slow)
    assert np.all(got <= 1.0) and got.min() < 0.1  # it does habituate
