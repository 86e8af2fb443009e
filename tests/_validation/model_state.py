"""A fitted detector and a deep snapshot of its state: a rejected call must leave it exactly as it was."""

import copy

import numpy as np

import novelty
from tests.damaged import damaging

N_FEATURES = 4


def fitted():
    det = novelty.make("hsom", n_rows=3, n_columns=3)
    det.fit(np.random.default_rng(0).uniform(size=(20, N_FEATURES)))
    with damaging(det):
        det.synapse_.efficacy_[:] = np.linspace(0.1, 0.9, 9)  # not all equal, so any change shows
    return det


#: not state: how many times attributes were set (novelty._component.Component.__setattr__), the
#: counts the filter last checked its parts at, the detector's lock (a deep copy makes a new one)
#: and its engine (scratch: a deep copy holds what its own is made from), a fitted part's marks of the
#: engine that holds and writes it (novelty._component.held_by_engine, engine_writes)
BOOKKEEPING = ("_changes", "_parts_seen", "_lock", "_engine", "_held", "_writing", "_locked")


def snapshot(det):
    """A deep copy of every attribute of the detector and of its fitted parts."""
    snap = {"detector": copy.deepcopy({k: v for k, v in vars(det).items()
                                       if k not in ("clusterer_", "synapse_") + BOOKKEEPING})}
    for part in ("clusterer_", "synapse_"):
        if hasattr(det, part):
            snap[part] = copy.deepcopy({k: v for k, v in vars(getattr(det, part)).items() if k not in BOOKKEEPING})
    return snap


def assert_equal_deep(a, b, where="state"):
    if isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray) and a.dtype == b.dtype, where
        np.testing.assert_array_equal(a, b, err_msg=where)
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            assert_equal_deep(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, (list, tuple)):
        assert type(a) is type(b) and len(a) == len(b), where
        for i, (u, v) in enumerate(zip(a, b)):
            assert_equal_deep(u, v, f"{where}[{i}]")
    elif hasattr(a, "get_params"):
        assert repr(a.get_params()) == repr(b.get_params()), where
    else:
        assert a == b, where
