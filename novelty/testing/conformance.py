"""The conformance suite: checks every clusterer, synapse and detector must pass.

Plugin authors run it on their own components, the way scikit-learn's
``check_estimator`` is used::

    from novelty.testing import conformance_checks

    @pytest.mark.parametrize("check", conformance_checks(MyClusterer()), ids=lambda c: c.__name__)
    def test_my_clusterer(check):
        check()

or in one call, ``check_conformance(MyClusterer())``. The project's own test
suite runs it over every registered name, so a new component is checked
without new test code.

Each check builds what it needs from the component's parameters (it clones
the instance), so the instance given is never modified.
"""

from __future__ import annotations

import functools
import importlib.util
import tempfile
from pathlib import Path
from typing import Callable, Iterator

import numpy as np
from sklearn.base import clone

from ..clusterers.base import Clusterer, Growth, Match
from ..detector import NoveltyDetector
from ..habituation.base import Synapse
from ..registry import detectors

__all__ = ["conformance_checks", "check_conformance", "installed_detectors"]

N_FEATURES = 5


def _data(seed: int = 0, n: int = 120, n_features: int = N_FEATURES) -> np.ndarray:
    """A smooth random walk in [0, 1]^d, like a robot's consecutive sonar scans."""
    rng = np.random.default_rng(seed)
    steps = rng.normal(scale=0.08, size=(n, n_features))
    return np.clip(0.5 + np.cumsum(steps, axis=0), 0.0, 1.0)


def _state_arrays(obj) -> dict[str, np.ndarray]:
    """Every learned array of ``obj`` and of its nested components, by path."""
    arrays, values, children = obj._export_state()
    out = {name: np.array(a, copy=True) for name, a in arrays.items()}
    out.update({f"value:{k}": np.array(repr(v)) for k, v in values.items()})
    for name, child in children.items():
        out.update({f"{name}/{k}": v for k, v in _state_arrays(child).items()})
    return out


def _assert_same_state(before: dict, after: dict, what: str) -> None:
    assert before.keys() == after.keys(), f"{what}: the set of learned attributes changed"
    for key in before:
        assert np.array_equal(before[key], after[key]), f"{what}: '{key}' changed"


def _check(fn: Callable) -> Callable:
    fn.__conformance__ = True
    return fn


def _named(fn: Callable, component) -> Callable:
    bound = functools.partial(fn, component)
    bound.__name__ = fn.__name__
    return bound


# ----------------------------------------------------------------- clusterers
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
    from ..filter import HabituatingFilter

    X = _data()
    det = HabituatingFilter(clusterer=clone(c)).fit(X)
    assert det.synapse_.n_units_ == det.clusterer_.n_units_, "the synapse bank must follow the units"
    out = det.novelty(X)
    rest = det.synapse_.resting_efficacy
    assert np.all((out >= rest - 1e-12) & (out <= det.synapse_.y0 + 1e-12))


# ------------------------------------------------------------------- synapses
def _new_bank(s: Synapse, n: int = 6) -> Synapse:
    return clone(s).initialize(n)


@_check
def check_synapse_initialize(s: Synapse) -> None:
    bank = _new_bank(s)
    assert bank.efficacy_.shape == (6,)
    assert np.all(np.isfinite(bank.efficacy_))
    assert np.all(bank.efficacy_ == bank.efficacy_[0]), "fresh synapses are all alike"
    assert bank.resting_efficacy < bank.efficacy_[0], "habituation must lower the efficacy"


@_check
def check_synapse_habituates_and_is_bounded(s: Synapse) -> None:
    bank = _new_bank(s)
    start = bank.efficacy_[0]
    previous = start
    for _ in range(200):
        bank.step(0, np.array([1]))
        y = bank.efficacy_[0]
        assert y <= previous + 1e-12, "a constant stimulus must not raise the winner's efficacy"
        assert y >= bank.resting_efficacy - 1e-9, "efficacy must not fall below its resting value"
        previous = y
    assert bank.efficacy_[0] < start and bank.efficacy_[1] < start, "winner and neighbour habituate"
    assert abs(bank.efficacy_[0] - bank.resting_efficacy) < 1e-3, "a long stimulus reaches the resting value"


@_check
def check_synapse_hold_rule(s: Synapse) -> None:
    bank = _new_bank(clone(s).set_params(others="hold"))
    bank.step(0, np.array([1]))
    untouched = bank.efficacy_[2:].copy()
    for _ in range(5):
        bank.step(0, np.array([1]))
    assert np.array_equal(bank.efficacy_[2:], untouched), "with others='hold' other units keep their value"


@_check
def check_synapse_forget_rule(s: Synapse) -> None:
    bank = _new_bank(clone(s).set_params(others="forget"))
    for _ in range(10):
        bank.step(2, np.array([], dtype=np.intp))
    low = bank.efficacy_[2]
    for _ in range(10):
        bank.step(0, np.array([], dtype=np.intp))
    assert bank.efficacy_[2] > low, "with others='forget' an unstimulated synapse recovers"


@_check
def check_synapse_grow_shrink(s: Synapse) -> None:
    bank = _new_bank(s)
    for i in range(6):
        for _ in range(i):
            bank.step(i, np.array([], dtype=np.intp))
    before = bank.efficacy_.copy()
    bank.shrink(np.array([1, 4]))
    assert np.array_equal(bank.efficacy_, before[[0, 2, 3, 5]]), "shrink removes exactly the given rows"
    bank.grow(2)
    assert bank.n_units_ == 6 and np.all(bank.efficacy_[-2:] == clone(s).initialize(1).efficacy_[0])
    for name in type(bank)._per_unit:
        assert getattr(bank, name).shape[0] == 6, f"{name} must grow and shrink with the bank"


@_check
def check_synapse_dt(s: Synapse) -> None:
    small, big = _new_bank(s), _new_bank(s)
    small.step(0, np.array([], dtype=np.intp), dt=0.5)
    big.step(0, np.array([], dtype=np.intp), dt=2.0)
    assert big.efficacy_[0] < small.efficacy_[0], "a longer stimulus habituates more"


# ------------------------------------------------------------------ detectors
def installed_detectors() -> list[str]:
    """Registered detector names whose optional dependencies (``requires``) are installed."""
    return [name for name in detectors.names()
            if all(importlib.util.find_spec(m) is not None for m in getattr(detectors.make(name), "requires", ()))]


@_check
def check_detector_fit_and_novelty(d: NoveltyDetector) -> None:
    X = _data()
    det = clone(d).fit(X)
    out = det.novelty(X)
    assert out.shape == (X.shape[0],) and np.all(np.isfinite(out))
    assert det.n_features_in_ == X.shape[1]
    assert np.array_equal(det.score_samples(X), -out), "score_samples is -novelty"
    pred = det.predict(X)
    assert set(np.unique(pred)) <= {-1, 1}
    assert np.array_equal(pred == -1, out > det.threshold)


@_check
def check_detector_novelty_is_pure(d: NoveltyDetector) -> None:
    X = _data()
    det = clone(d).fit(X)
    before = _state_arrays(det)
    first = det.novelty(X)
    det.score_one(X[0])
    det.predict(X)
    _assert_same_state(before, _state_arrays(det), "scoring must not change the model")
    assert np.array_equal(first, det.novelty(X))
    assert np.isclose(det.score_one(X[3]), first[3], rtol=1e-12, atol=1e-12), "score_one equals novelty()"


@_check
def check_detector_deterministic(d: NoveltyDetector) -> None:
    X = _data()
    a, b = clone(d).fit(X), clone(d).fit(X)
    assert np.array_equal(a.novelty(X), b.novelty(X)), "same parameters and data, same novelty"


@_check
def check_detector_rejects_bad_input(d: NoveltyDetector) -> None:
    X = _data()
    det = clone(d).fit(X)
    before = _state_arrays(det)
    methods = ("novelty", "partial_fit", "fit") if det.supports_online else ("novelty", "fit")
    cases = [(X[:, :-1], [m for m in methods if m != "fit"])]  # a refit may change width
    cases += [(bad, methods) for bad in (np.full_like(X[:3], np.nan), np.empty((0, X.shape[1])), X[None])]
    for bad, names in cases:
        for method in names:
            try:
                getattr(det, method)(bad)
            except ValueError:
                pass
            else:
                raise AssertionError(f"{method} accepted bad input of shape {bad.shape}")
            _assert_same_state(before, _state_arrays(det), f"a rejected {method} must leave the model unchanged")


@_check
def check_detector_online(d: NoveltyDetector) -> None:
    if not d.supports_online:
        return
    X = _data()
    # Start both from the same state: some networks initialise from the first batch.
    a, b = clone(d).fit(X[:20]), clone(d).fit(X[:20])
    streamed = a.stream(X[20:])
    one_by_one = np.array([b.score_learn_one(x) for x in X[20:]])
    assert np.allclose(streamed, one_by_one, rtol=1e-12, atol=1e-12), "stream() equals score_learn_one() row by row"
    _assert_same_state(_state_arrays(a), _state_arrays(b), "stream() and score_learn_one() must learn alike")


@_check
def check_detector_save_load(d: NoveltyDetector) -> None:
    from ..persistence import load

    X = _data()
    det = clone(d).fit(X[:80])
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model.npz"
        det.save(path)
        back = load(path)
    assert type(back) is type(det)
    assert np.array_equal(det.novelty(X), back.novelty(X)), "a loaded model scores identically"
    if det.supports_online:
        assert np.array_equal(det.stream(X[80:]), back.stream(X[80:])), "and learns identically"


_CHECKS = {
    Clusterer: [
        check_clusterer_initialize,
        check_clusterer_deterministic,
        check_clusterer_match,
        check_clusterer_match_is_pure,
        check_clusterer_winners_equal_match,
        check_clusterer_adapt_moves_winner_closer,
        check_clusterer_growth_is_consistent,
        check_clusterer_state_round_trip,
        check_clusterer_in_filter,
    ],
    Synapse: [
        check_synapse_initialize,
        check_synapse_habituates_and_is_bounded,
        check_synapse_hold_rule,
        check_synapse_forget_rule,
        check_synapse_grow_shrink,
        check_synapse_dt,
    ],
    NoveltyDetector: [
        check_detector_fit_and_novelty,
        check_detector_novelty_is_pure,
        check_detector_deterministic,
        check_detector_rejects_bad_input,
        check_detector_online,
        check_detector_save_load,
    ],
}


def conformance_checks(component) -> Iterator[Callable[[], None]]:
    """The checks that apply to ``component``, each a no-argument callable."""
    for base, checks in _CHECKS.items():
        if isinstance(component, base):
            for fn in checks:
                yield _named(fn, component)
            return
    raise TypeError(f"{type(component).__name__} is not a Clusterer, Synapse or NoveltyDetector.")


def check_conformance(component) -> None:
    """Run every applicable check; raise AssertionError on the first failure."""
    for check in conformance_checks(component):
        try:
            check()
        except AssertionError as exc:
            raise AssertionError(f"{type(component).__name__} fails {check.__name__}: {exc}") from exc
