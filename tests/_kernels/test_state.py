"""What an engine reads is checked in one place (novelty._kernels.state), whatever the route.

The cases that crashed or read past an array run in a child process: a crash there fails
the test instead of ending the run.
"""

from __future__ import annotations

import contextlib
import copy
import json
import subprocess
import sys

import numpy as np
import pytest

import novelty
from novelty import _kernels
from novelty._component import StateError
from novelty._kernels.state import check_state

from tests.damaged import damaging

from .kernel_helpers import corridor, reference_only

#: what the child runs: a fitted hsom (kernels ready), each case's state set on a copy, each
#: call's outcome printed as JSON: the error's type and message, or "ok"
CHILD = r"""
import copy, json, sys
import numpy as np
import novelty
from novelty import _kernels
from novelty._component import engine_writes
from novelty._kernels.state import parts_of

X = np.random.default_rng(0).uniform(0, 1, (200, 16))
fitted = novelty.make("hsom").fit(X)
_kernels.wait(fitted.clusterer_, fitted.synapse_)
_kernels.wait()
fitted.novelty(X[:2])  # an engine chosen with every kernel ready

def wide(det):  # the issue's case: 8 GB of zeros, never touched (numpy's zeros are lazy)
    det.clusterer_.weights_ = np.zeros((100, 10_000_000))

CASES = {
    "wider by 10 million": wide,
    "wider by 48": lambda det: setattr(det.clusterer_, "weights_", np.zeros((100, 64))),
    "wider by 1e5": lambda det: setattr(det.clusterer_, "weights_", np.zeros((100, 100_000))),
    "narrower": lambda det: setattr(det.clusterer_, "weights_", np.zeros((100, 8))),
    "fewer units": lambda det: setattr(det.clusterer_, "weights_", np.zeros((50, 16))),
    "a larger grid": lambda det: setattr(det.clusterer_, "n_rows", 20),
    "n_features_in_": lambda det: setattr(det, "n_features_in_", 8),
}
CALLS = {
    "stream": lambda det, X: det.stream(X),
    "novelty": lambda det, X: det.novelty(X),
    "score_one": lambda det, X: det.score_one(X[0]),
    "score_learn_one": lambda det, X: det.score_learn_one(X[0]),
}
out = {}
for case, hostile in CASES.items():
    for call, run in CALLS.items():
        det = copy.deepcopy(fitted)
        det.score_learn_one(X[0])  # the single-scan calls' engine confirmed
        with engine_writes(parts_of(det.clusterer_, det.synapse_)):  # as tests.damaged does
            hostile(det)
        scans = X[:, :8] if case == "n_features_in_" else X
        try:
            run(det, scans)
            out[case + " / " + call] = "ok"
        except Exception as exc:
            out[case + " / " + call] = type(exc).__name__ + ": " + str(exc)
        print(json.dumps({case + " / " + call: out[case + " / " + call]}), flush=True)
"""


@pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")
def test_a_state_the_loops_would_read_past_is_refused_not_read():
    """Weights wider or narrower than the scans, fewer units than the map's grid, a grid
    enlarged after fitting, n_features_in_ set by hand: each call refuses with a StateError
    that names what is wrong (before: a segmentation fault for the widest, reads past each
    scan for the others, "damaged state" or silently wrong scores)."""
    child = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=600)
    assert child.returncode == 0, f"the child ended with {child.returncode}: {child.stderr[-2000:]}"
    outcomes = {}
    for line in child.stdout.splitlines():
        outcomes.update(json.loads(line))
    assert len(outcomes) == 28
    for key, outcome in outcomes.items():
        case = key.split(" / ")[0]
        assert outcome.startswith("StateError: "), (key, outcome)
        expected = {"fewer units": "efficacy_ has shape (100,); with 50 units",
                    "a larger grid": "SOM.weights_ has 100 units; a 20 x 10 map has 200",
                    "n_features_in_": "n_features_in_"}.get(case, "clusterer_.weights_ has shape")
        assert expected in outcome, (key, outcome)


def test_the_checks_name_what_is_wrong():
    X = corridor(40, n_features=4)
    det = novelty.make("gng-stanley").fit(X)
    check_state(det)  # a fitted state passes
    cases = [
        (lambda d: setattr(d.clusterer_, "errors_", d.clusterer_.errors_[:-1]),
         r"clusterer_\.errors_ has shape \(\d+,\); with \d+ units"),
        (lambda d: setattr(d.clusterer_, "edge_ages_", d.clusterer_.edge_ages_[:, :-1]),
         r"edge_ages_ has shape .* it has shape \(\d+, \d+\)"),
        (lambda d: setattr(d.synapse_, "efficacy_", np.ones(3)), r"synapse_\.efficacy_ has shape \(3,\)"),
        (lambda d: setattr(d.clusterer_, "n_inputs_", -1), r"n_inputs_ must be an int in \[0, 2\*\*53\]; got -1"),
        (lambda d: setattr(d.clusterer_, "next_unit_id_", 2**70), r"next_unit_id_ must be an int in"),
        (lambda d: setattr(d.clusterer_, "errors_", d.clusterer_.errors_.astype(np.float32)),
         r"errors_ must be a float64 array; got float32"),
        (lambda d: setattr(d.clusterer_, "unit_ids_", d.clusterer_.unit_ids_.astype(object)),
         r"unit_ids_ holds object values"),
        (lambda d: d.clusterer_.weights_.__setitem__((0, 0), np.nan), r"weights_ (holds|contains) NaN or infinity"),
        (lambda d: setattr(d.clusterer_, "max_age", 0), r"The 'max_age' parameter of GrowingNeuralGas"),
        (lambda d: setattr(d.clusterer_, "weights_", list(d.clusterer_.weights_)), r"must be a numpy array"),
    ]
    for change, message in cases:
        hostile = copy.deepcopy(det)
        with damaging(hostile):
            change(hostile)
        with pytest.raises(StateError, match=message):
            check_state(hostile)


@pytest.mark.parametrize("reference", [False, True])
def test_values_written_in_place_are_checked_before_every_batch_call(reference):
    X = corridor(60, n_features=5)
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(X)
    with reference_only() if reference else contextlib.nullcontext():
        det.stream(X[:10])
        with damaging(det):
            det.clusterer_.weights_[2, 1] = np.nan  # in place: no change counted
        with pytest.raises(StateError, match=r"SOM\.weights_ holds NaN or infinity"):
            det.stream(X[10:20])
        with pytest.raises(StateError, match=r"SOM\.weights_ holds NaN or infinity"):
            det.novelty(X[10:20])



@pytest.mark.parametrize("reference", [False, True])
def test_an_efficacy_beyond_the_bound_written_in_place_is_refused(reference):
    """A firing counter's efficacy of 1e300 written in place (finite, so check_finite passes) would
    carry a growing network's weights past what a float holds within the call, where the compiled
    winner search and numpy's argmin part ways: every call refuses it, single scans too."""
    X = corridor(60, n_features=5)
    det = novelty.make("habituating", clusterer="gwr", synapse="stanley").fit(X)
    if not reference:
        _kernels.wait()
    with reference_only() if reference else contextlib.nullcontext():
        det.score_learn_one(X[0].copy())
        with damaging(det):
            det.clusterer_.firing_.efficacy_[0] = 1e300
        message = r"StanleySynapse\.efficacy_ holds a value beyond 1e\+100"
        for call in (det.stream, det.novelty, det.partial_fit):
            with pytest.raises(StateError, match=message):
                call(X[1:4])
        for call in (det.score_learn_one, det.score_one):
            with pytest.raises(StateError, match=message):
                call(X[1].copy())


@pytest.mark.parametrize("reference", [False, True])
@pytest.mark.parametrize("value, message", [(np.nan, r"SOM\.weights_ holds NaN or infinity"),
                                            (1e300, r"SOM\.weights_ reach a norm of 1e\+300, beyond the bound")])
def test_values_written_in_place_are_checked_before_a_single_scan(reference, value, message):
    """A value written into the weights in place after a single scan confirmed the engine: the
    next single scan refuses it as a batch call does (before: the compiled winner search
    skipped the NaN unit where the reference's argmin took it, and a unit at 1e300, whose
    distances overflow, gave the two engines other graphs)."""
    X = corridor(60, n_features=5)
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(X)
    if not reference:
        assert _kernels.wait(det.clusterer_, det.synapse_) is not None
        _kernels.wait()
    with reference_only() if reference else contextlib.nullcontext():
        det.score_learn_one(X[0].copy())  # the single-scan protocol's engine confirmed
        with damaging(det):
            det.clusterer_.weights_[4, 2] = value
        for call in (det.score_learn_one, det.score_one):
            with pytest.raises(StateError, match=message):
                call(X[1].copy())
        with pytest.raises(StateError, match=message):
            det.stream(X[1:3])
