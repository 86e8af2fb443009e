"""The checks of a clusterer of world cells (several winners a scan: :mod:`novelty.maps.cells`).

It composes with a synapse in a :class:`~novelty.maps.habituating_map.HabituatingMap`, which the
detector checks run on its own; these check the clusterer in it, on the ``points`` input
(:func:`novelty.io.scans.points.example_rows`): a fresh map is empty, the same rows give the same map,
and its compiled loop (:mod:`novelty.maps.map_engine`) equals the numpy reference bit for bit, with a
forgetting Stanley synapse, neighbours, a visit gap and irregular timestamps (skipped without
numba, ``unittest.SkipTest``).
"""

from __future__ import annotations

import unittest

import numpy as np
from sklearn.base import clone

from .. import _kernels
from ..habituation.stanley import StanleySynapse
from ..maps.map_engine import wait
from ..maps.habituating_map import HabituatingMap
from ..io.scans.points import example_rows
from ._helpers import _check, _state_arrays

__all__ = ["check_cells_start_empty", "check_map_deterministic", "check_map_compiled_equals_reference"]


def _map(cells, **params) -> HabituatingMap:
    return HabituatingMap(clusterer=clone(cells).set_params(**params),
                          synapse=StanleySynapse(others="forget", tau_neighbour=6.0))


@_check
def check_cells_start_empty(cells) -> None:
    """A fresh map holds no cell, has learned no scan, and a first scan scores its unseen weight."""
    X = example_rows(seed=0, n=5)
    fresh = clone(cells).initialize(X)
    assert fresh.n_units_ == 0 and fresh.scans_ == 0 and fresh.pending_.shape == (0, X.shape[1])
    det = _map(cells)
    assert det.score_one(X[0]) == det.stream(X[:1])[0] == fresh.first_novelty(1.0)


@_check
def check_map_deterministic(cells) -> None:
    """The same rows give the same novelty and the same map, in one batch or row by row."""
    X = example_rows(seed=1, n=60)
    batch = _map(cells, neighbours=True).fit(X)
    rows = _map(cells, neighbours=True).fit(X[:1])
    out = [rows.stream(X[i:i + 1])[0] for i in range(1, X.shape[0])]
    assert np.array_equal(np.array(out), _map(cells, neighbours=True).fit(X[:1]).stream(X[1:]))
    for part in ("clusterer_", "synapse_"):
        a, b = _state_arrays(getattr(batch, part)), _state_arrays(getattr(rows, part))
        assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a), f"{part}: batch and row by row"


@_check
def check_map_compiled_equals_reference(cells) -> None:
    """The compiled loop learns and scores what the reference does, bit for bit."""
    X = np.vstack([example_rows(seed=2, n=150), example_rows(seed=3, n=150) + np.r_[[1.5, 0.0, 0.0],
                                                                                      np.zeros(8), np.full(8, 1.5),
                                                                                      np.zeros(8)]])
    t = np.cumsum(1.0 + np.random.default_rng(3).integers(0, 3, len(X)) * 0.5)
    params = {"neighbours": True, "visit_gap": 3, "evidence_lag": 2}
    fast = _map(cells, **params).fit(X[:1], timestamps=t[:1])
    if not _kernels.kernels_enabled():
        raise unittest.SkipTest("numba kernels unavailable")
    assert wait(fast.clusterer_, fast.synapse_), fast.compiled_
    got = fast.stream(X[1:], timestamps=t[1:]), fast.novelty(X)
    assert fast.compiled_ == "compiled", fast.compiled_
    with _kernels.reference_loops():
        slow = _map(cells, **params).fit(X[:1], timestamps=t[:1])
        expected = slow.stream(X[1:], timestamps=t[1:]), slow.novelty(X)
    name = type(cells).__name__
    np.testing.assert_array_equal(got[0], expected[0], err_msg=f"{name}: the novelty while learning")
    np.testing.assert_array_equal(got[1], expected[1], err_msg=f"{name}: the novelty after learning")
    a, b = _state_arrays(fast), _state_arrays(slow)
    assert a.keys() == b.keys(), f"{name}: the learned attributes differ"
    for key in a:
        np.testing.assert_array_equal(a[key], b[key], err_msg=f"{name}: '{key}'")
