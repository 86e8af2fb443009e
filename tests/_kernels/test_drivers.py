"""The drivers compose a plugin's steps: the guide's new synapse (``fading.py``) runs compiled
inside hsom's map, as the reference does, under the base class's schedule (hold or forget) and
with its own parameter read by name, and scores compiled; the drivers' folder is pruned."""

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


@pytest.mark.parametrize("others, gain", [("hold", 1.0), ("forget", 3.0)])
def test_the_guide_synapse_learns_compiled_as_the_reference(tmp_path, monkeypatch, others, gain):
    block = next(b for b in re.findall(r"```python\n(.*?)```", EXTENDING.read_text(encoding="utf-8"),
                                       flags=re.S) if b.startswith("# fading.py\n"))
    (tmp_path / "fading.py").write_text(block, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "fading", raising=False)
    Fading = importlib.import_module("fading").Fading
    X = corridor(400)
    # its own parameter, gain, is read by name in the compiled steps (p.gain)
    fast = novelty.HabituatingFilter(clusterer="som", synapse=Fading(others=others, gain=gain)).fit(X[:1])
    assert fast.compiled_ == "compiled"
    assert _kernels.wait(fast.clusterer_, fast.synapse_) is not None  # the pair's driver
    assert _kernels.scorer(fast.clusterer_, fast.synapse_) is not None  # batch scoring compiled
    got = fast.stream(X[1:]), fast.novelty(X)
    with reference_only():
        slow = novelty.HabituatingFilter(clusterer="som", synapse=Fading(others=others, gain=gain)).fit(X[:1])
        assert slow.compiled_ == "reference (NOVELTY_NO_KERNELS)"
        expected = slow.stream(X[1:]), slow.novelty(X)
    np.testing.assert_array_equal(got[0], expected[0])
    np.testing.assert_array_equal(got[1], expected[1])
    assert_same_filter(fast, slow)
    # it habituates towards 1 / (1 + gain), below which it never falls
    assert np.all(got[0] <= 1.0) and got[0].min() < 1.0 / (1.0 + gain) + 0.1
    assert got[0].min() >= 1.0 / (1.0 + gain)
# ------------------------------------------------------------------ the drivers' folder
def test_prune_keeps_the_recently_used_drivers_of_each_pair(tmp_path, monkeypatch):
    import os

    from novelty._kernels import drivers

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "numba"))
    cache = tmp_path / "numba" / "folder"
    cache.mkdir(parents=True)
    names = [f"{drivers.PREFIX}som_stanleysynapse_{i:016x}" for i in range(4)]
    names.append(f"{drivers.PREFIX}gng_stanleysynapse_{0:016x}")
    for age, name in enumerate(names):
        path = tmp_path / f"{name}.py"
        path.write_text("")
        (cache / f"{name}.drive-65.py312.nbi").write_text("")
        (cache / f"{name}.drive-65.py312.1.nbc").write_text("")
        os.utime(path, (1000 - age, 1000 - age))  # the first is the most recent
    drivers._mark_used(str(tmp_path / f"{names[3]}.py"))  # used now: the most recent of all
    (tmp_path / "unrelated.py").write_text("")
    stale = drivers.prune(str(tmp_path), keep_per_pair=2, keep=64)
    assert sorted(stale) == sorted(str(tmp_path / f"{n}.py") for n in names[1:3])
    left = sorted(p.name for p in tmp_path.glob("*.py"))
    assert left == sorted([f"{names[0]}.py", f"{names[3]}.py", f"{names[4]}.py", "unrelated.py"])
    assert sorted(p.name.split(".")[0] for p in cache.glob("*.nbi")) == sorted(
        [names[0], names[3], names[4]])
    assert len(list(cache.glob("*.nbc"))) == 3
    assert drivers.prune(str(tmp_path), keep_per_pair=2, keep=2) == [str(tmp_path / f"{names[4]}.py")]


def test_the_private_folder_without_user_ids(tmp_path, monkeypatch):
    """Where os.getuid does not exist (Windows), the temporary folder is the user's own."""
    from novelty._kernels import drivers

    blocked = tmp_path / "file"
    blocked.write_text("")  # a file where a folder would be: nothing can be made under it
    monkeypatch.setenv("NOVELTY_KERNEL_DIR", str(blocked / "drivers"))
    monkeypatch.setattr(drivers.tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.delattr(drivers.os, "getuid")
    assert drivers.folder() == str(tmp_path / "novelty-drivers")
