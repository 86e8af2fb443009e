"""The conformance checks every clusterer must pass (run through :mod:`novelty.testing.conformance`)."""

from __future__ import annotations

import numpy as np
from sklearn.base import clone

from ..clusterers.base import Clusterer, Growth, Match
from ..filter import HabituatingFilter
from ._helpers import _assert_same_state, _check, _data, _state_arrays

def _new_clusterer(c: Clusterer, X: np.ndarray, seed: int = 0) -> Clusterer:
    return clone(c).initialize(X, random_state=seed)


def _apply(c: Clusterer, x: np.ndarray) -> tuple[Match, Growth, np.ndarray]:
    ids_before = c.unit_ids_.copy()
    match, growth = c.learn_one(x)
    return match, growth, ids_before


@_check
def check_clusterer_initialize(c: Clusterer) -> None:
    X = _data()
    net = _new_clusterer(c, X)
    assert net.weights_.ndim == 2 and net.weights_.shape[1] == X.shape[1], "weights_ must be (n_units, n_features)"
    assert net.n_units_ >= 1
    assert net.unit_ids_.shape == (net.n_units_,)
    assert len(np.unique(net.unit_ids_)) == net.n_units_, "unit ids must be unique"
    assert np.all(np.isfinite(net.weights_))


@_check
def check_clusterer_deterministic(c: Clusterer) -> None:
    X = _data()
    a, b = _new_clusterer(c, X, 7), _new_clusterer(c, X, 7)
    for x in X:
        a.learn_one(x)
        b.learn_one(x)
    assert np.array_equal(a.weights_, b.weights_), "same seed and inputs must give identical weights"
    assert np.array_equal(a.unit_ids_, b.unit_ids_)


@_check
def check_clusterer_match(c: Clusterer) -> None:
    X = _data()
    net = _new_clusterer(c, X)
    for x in X[:30]:
        m = net.match(x)
        d = ((net.weights_ - x) ** 2).sum(axis=1)
        assert 0 <= m.winner < net.n_units_
        assert d[m.winner] == d.min(), "the winner must be the unit of least squared distance"
        assert np.isclose(m.distance, d[m.winner], rtol=1e-12, atol=1e-12)
        nb = np.asarray(m.neighbours)
        assert m.winner not in nb, "the winner is not its own neighbour"
        assert len(np.unique(nb)) == len(nb) and np.all((nb >= 0) & (nb < net.n_units_))
        net.learn_one(x)


@_check
def check_clusterer_match_is_pure(c: Clusterer) -> None:
    X = _data()
    net = _new_clusterer(c, X)
    for x in X[:20]:
        net.learn_one(x)
    before = _state_arrays(net)
    net.match(X[50])
    net.winners(X)
    _assert_same_state(before, _state_arrays(net), "match()/winners() must not learn")


@_check
def check_clusterer_winners_equal_match(c: Clusterer) -> None:
    X = _data()
    net = _new_clusterer(c, X)
    for x in X[:60]:
        net.learn_one(x)
    rows, dist = net.winners(X)
    expected = np.array([net.match(x).winner for x in X])
    assert np.array_equal(rows, expected), "vectorised winners must equal per-input match()"
    assert np.allclose(dist, [net.match(x).distance for x in X], rtol=1e-9, atol=1e-12)


@_check
def check_clusterer_adapt_moves_winner_closer(c: Clusterer) -> None:
    X = _data()
    net = _new_clusterer(c, X)
    for x in X:
        ids = net.unit_ids_.copy()
        m = net.match(x)
        winner_id = ids[m.winner]
        growth = net.adapt(x, m)
        if winner_id in net.unit_ids_:
            row = int(np.flatnonzero(net.unit_ids_ == winner_id)[0])
            after = ((net.weights_[row] - x) ** 2).sum()
            assert after <= m.distance + 1e-12, "adapting must not move the winner away from the input"
        assert isinstance(growth, Growth)


@_check
def check_clusterer_growth_is_consistent(c: Clusterer) -> None:
    X = np.vstack([_data(0), _data(1) * 0.3 + 0.7])
    net = _new_clusterer(c, X)
    for x in X:
        ids_before = net.unit_ids_.copy()
        _, growth = net.learn_one(x)
        removed = np.asarray(growth.removed, dtype=np.intp)
        assert np.all(np.diff(removed) > 0), "removed rows must be sorted and unique"
        kept = np.delete(ids_before, removed)
        assert net.n_units_ == len(kept) + growth.added, "n_units must follow the reported growth"
        assert np.array_equal(net.unit_ids_[: len(kept)], kept), "surviving units keep their ids and order"
        new = net.unit_ids_[len(kept):]
        assert np.all(new >= net.next_unit_id_ - growth.added) and len(np.unique(net.unit_ids_)) == net.n_units_
        assert net.weights_.shape[0] == net.n_units_


@_check
def check_clusterer_state_round_trip(c: Clusterer) -> None:
    X = _data()
    net = _new_clusterer(c, X)
    for x in X[:40]:
        net.learn_one(x)
    arrays, values, children = net._export_state()
    copy = clone(net)
    copy._import_state({k: np.array(v) for k, v in arrays.items()}, dict(values), {
        k: _roundtrip_child(v) for k, v in children.items()})
    for x in X[40:]:
        assert net.match(x).winner == copy.match(x).winner
        net.learn_one(x)
        copy.learn_one(x)
    _assert_same_state(_state_arrays(net), _state_arrays(copy), "exported and re-imported state must learn alike")


def _roundtrip_child(child):
    arrays, values, children = child._export_state()
    copy = clone(child)
    copy._import_state({k: np.array(v) for k, v in arrays.items()}, dict(values),
                       {k: _roundtrip_child(v) for k, v in children.items()})
    return copy


@_check
def check_clusterer_in_filter(c: Clusterer) -> None:
    X = _data()
    det = HabituatingFilter(clusterer=clone(c)).fit(X)
    assert det.synapse_.n_units_ == det.clusterer_.n_units_, "the synapse bank must follow the units"
    out = det.novelty(X)
    rest = det.synapse_.resting_efficacy
    assert np.all((out >= rest - 1e-12) & (out <= det.synapse_.y0 + 1e-12))
