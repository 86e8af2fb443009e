"""A hostile state gives the compiled engine's answer the reference's: the same numbers, or the
same error; never a crash, a read past an array or another winner.

Every pair that runs compiled (each registered clusterer with each registered synapse, and the
guide's plugins: ``tests/_kernels/hostile.py``) is fitted; then one state array, counter or
parameter of a fitted part is replaced by a hostile value (wider, narrower, fewer or more units,
strided, Fortran-ordered, read-only, NaN or infinity, negative or huge counts, another type), or
written into in place, or set by ``set_params``, before the engine read the state or after; then
the filter streams, scores or learns one scan. The compiled engine runs in a child process (one
for all cases, restarted after a crash), so that a crash fails the case instead of ending the
run; the reference runs here, with ``NOVELTY_NO_KERNELS`` set. Both outcomes, each call's result
bytes or error type and message and a digest of the state after the calls, must be equal.
"""

from __future__ import annotations

import json
import os
import selectors
import signal
import subprocess
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from novelty import _kernels

from . import hostile
from .kernel_helpers import reference_only

# slow: a child process of its own (17 s on one core, warm), run by CI's slow set and kernel checks
pytestmark = [pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable"),
              pytest.mark.slow]

PAIRS = hostile.pairs()
#: the longest a case may take in the child (its first cases load or compile the pair's kernels)
TIMEOUT = 600.0


class Child:
    """The compiled side: a child process running :func:`hostile.serve`, restarted after a
    crash; :meth:`run` answers a case's outcome or fails the test with how the child ended."""

    def __init__(self):
        self.process = None

    def start(self):
        env = {k: v for k, v in os.environ.items() if k != "NOVELTY_NO_KERNELS"}
        self.process = subprocess.Popen([sys.executable, hostile.__file__, hostile.plugin_folder()],
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True, env=env)

    def run(self, case: dict) -> dict:
        if self.process is None or self.process.poll() is not None:
            self.start()
        process = self.process
        process.stdin.write(json.dumps(case) + "\n")
        process.stdin.flush()
        with selectors.DefaultSelector() as selector:
            selector.register(process.stdout, selectors.EVENT_READ)
            ready = selector.select(TIMEOUT)
        line = process.stdout.readline() if ready else ""
        if line:
            return json.loads(line)
        if not ready:
            process.kill()
        code = process.wait()
        self.process = None
        how = f"signal {signal.Signals(-code).name}" if code < 0 else f"exit status {code}"
        pytest.fail(f"the compiled engine's process ended with {how} on {case}:\n"
                    f"{process.stderr.read()[-3000:]}")

    def close(self):
        if self.process is not None and self.process.poll() is None:
            self.process.stdin.close()
            self.process.wait(timeout=60)


@pytest.fixture(scope="module")
def child():
    compiled = Child()
    yield compiled
    compiled.close()


def check(child: Child, case: dict) -> None:
    """The case's outcome compiled (in the child) equals the reference's (here)."""
    with reference_only():
        expected = hostile.run_case(case, hostile.plugin_folder())
    got = child.run(case)
    assert expected["engine"] == "ReferenceEngine"
    # the child's learning or scoring runs compiled, but for the plugin that declares neither
    assert got["engine"] == ("ReferenceEngine" if "Leader" in PAIRS[case["pair"]][0] else "CompiledEngine")
    for key in ("mutation", "calls", "state"):
        assert got[key] == expected[key], (f"{key} differs for {case}:\ncompiled  {got[key]}\n"
                                           f"reference {expected[key]}")


#: the targets of each pair (fitted by the reference), by kind
_targets: dict = {}


def targets_of(pair: int) -> dict:
    if pair not in _targets:
        with reference_only():
            _targets[pair] = hostile.targets(hostile.fitted(pair, hostile.plugin_folder()))
    return _targets[pair]


@st.composite
def cases(draw, pair: int):
    found = targets_of(pair)
    target = draw(st.sampled_from(sorted(found)))
    what = found[target]
    if what == "array":
        kind = draw(st.sampled_from(sorted(hostile.ARRAY_KINDS)))
        arg = draw(st.sampled_from(hostile.ARRAY_KINDS[kind]))
    else:
        kind, arg = what, draw(st.sampled_from(hostile.COUNT_VALUES if what == "count" else hostile.PARAM_VALUES))
    return {"pair": pair, "warm": draw(st.booleans()), "target": target, "kind": kind, "arg": arg,
            "seed": draw(st.integers(0, 2**16)),
            "calls": draw(st.lists(st.sampled_from(hostile.CALLS), min_size=1, max_size=3))}


@pytest.mark.parametrize("pair", range(len(PAIRS)), ids=["-".join(p) for p in PAIRS])
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_a_hostile_state_gives_the_reference_answer(child, pair, data):
    check(child, data.draw(cases(pair)))


@pytest.mark.parametrize("pair", range(len(PAIRS)), ids=["-".join(p) for p in PAIRS])
def test_every_kind_of_hostile_weights(child, pair):
    """Every mutation of the weights, before the engine read them and after, streamed and
    scanned alone: among them the weights (100, 10**7) that crashed the compiled loops."""
    for kind, args in hostile.ARRAY_KINDS.items():
        for arg in args:
            for warm, calls in ((False, ["stream", "novelty"]), (True, ["score_learn_one", "score_one"])):
                check(child, {"pair": pair, "warm": warm, "target": "clusterer_.weights_", "kind": kind,
                              "arg": arg, "seed": 0, "calls": calls})
