"""The drivers compose a plugin's steps: the guide's new synapse (``fading.py``) runs compiled
inside hsom's map, as the reference does, under the base class's schedule (hold or forget) and
with its own parameter read by name, and scores compiled; so does a plugin clusterer whose
parameters include None and an option string; the drivers' folder is pruned."""

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
#: a plugin clusterer with compiled steps, in a file of its own: online k-means whose runner-up
#: learns too when mode="pair", at its own rate or, when that is None, the winner's
TINY = """
import numbers
import numpy as np
from numba import njit
import novelty
from novelty import KernelSpec
from novelty.clusterers import Clusterer, Growth, Match
from novelty.rules import Interval, Options, option_code

class Tiny(Clusterer):
    _parameter_rules = {"n_units": Interval(numbers.Integral, 1, None),
                        "rate": Interval(numbers.Real, 0, 1),
                        "runner_up_rate": Interval(numbers.Real, 0, 1, allow_none=True),
                        "mode": Options(("winner", "pair"))}
    _capabilities = frozenset({"nearest-unit"})
    _kernel = KernelSpec(steps="tiny", params=("rate", "runner_up_rate", "mode"), ignores=("n_units",))
    def __init__(self, n_units=5, rate=0.25, runner_up_rate=None, mode="pair"):
        self.n_units, self.rate, self.runner_up_rate, self.mode = n_units, rate, runner_up_rate, mode
    def _initialize(self, X, rng):
        self.weights_ = rng.uniform(0, 1, (self.n_units, X.shape[1]))
    def match(self, x):
        d = novelty.squared_distances(self.weights_, x)
        w = int(d.argmin())
        distance = float(d[w])
        if self.mode == "winner" or len(d) < 2:
            return Match(w, distance, np.empty(0, dtype=np.intp))
        d[w] = np.inf
        return Match(w, distance, np.array([int(d.argmin())], dtype=np.intp))
    def adapt(self, x, match):
        rate = self.rate if self.runner_up_rate is None else self.runner_up_rate
        for j in match.neighbours:
            self.weights_[j] += rate * (x - self.weights_[j])
        self.weights_[match.winner] += self.rate * (x - self.weights_[match.winner])
        return Growth()

PAIR = option_code(Tiny, "mode", "pair")

@njit
def match(d, n, state, counters, p, nb):
    s = 0
    for j in range(1, n):
        if d[j] < d[s]:
            s = j
    if p.mode != PAIR or n < 2:
        return s, -1, 0
    t = -1
    for j in range(n):
        if j != s and (t < 0 or d[j] < d[t]):
            t = j
    nb[0] = t
    return s, t, 1

@njit
def room(d, winner, n, state, counters, p):
    return 0

@njit
def adapt(WT, x, d, winner, runner_up, nb, k, n, state, counters, p, gone):
    rate = p.runner_up_rate if p.has_runner_up_rate else p.rate
    for m in range(k):
        for f in range(WT.shape[0]):
            WT[f, nb[m]] += rate * (x[f] - WT[f, nb[m]])
    for f in range(WT.shape[0]):
        WT[f, winner] += p.rate * (x[f] - WT[f, winner])
    return n, 0, 0, False
"""


@pytest.mark.parametrize("params", [{}, {"runner_up_rate": 0.5}, {"mode": "winner", "rate": 0.75}])
def test_a_plugin_clusterer_reads_its_parameters_by_name_compiled(tmp_path, monkeypatch, params):
    """A clusterer of one's own, with a parameter that may be None and an option string, learns
    and scores compiled, bit for bit as its reference, with any synapse."""
    (tmp_path / "tiny.py").write_text(TINY, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "tiny", raising=False)
    Tiny = importlib.import_module("tiny").Tiny
    novelty.testing.check_kernel_declares_every_parameter(Tiny(**params))
    novelty.testing.check_compiled_equals_reference(Tiny(**params))  # paired with a forgetting bank
    X = corridor(200)
    fast = novelty.HabituatingFilter(clusterer=Tiny(**params), synapse="wang-hsu").fit(X[:1])
    assert _kernels.wait(fast.clusterer_, fast.synapse_) is not None
    assert fast.compiled_ == "compiled"
    got = fast.stream(X[1:])
    with reference_only():
        slow = novelty.HabituatingFilter(clusterer=Tiny(**params), synapse="wang-hsu").fit(X[:1])
        expected = slow.stream(X[1:])
    np.testing.assert_array_equal(got, expected)
    assert_same_filter(fast, slow)


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
