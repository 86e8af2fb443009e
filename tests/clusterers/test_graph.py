"""The graph of the growing networks: from any stream or any valid state, GNG and GWR keep the
edges symmetric, every unit connected, and the unit ids unique, increasing and stable."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.clusterers.gng import GrowingNeuralGas
from novelty.clusterers.gwr import GrowWhenRequired


streams = st.integers(1, 3).flatmap(lambda d: st.lists(
    st.lists(st.sampled_from([0.0, 0.125, 0.25, 0.5, 0.75, 1.0]), min_size=d, max_size=d),
    min_size=2, max_size=40))


def _learn_and_check(net, x):
    """Learn ``x``; check the match was the arg-min and the graph and ids are consistent afterwards."""
    ids_before, d = net.unit_ids_.copy(), ((net.weights_ - x) ** 2).sum(axis=1)
    m, growth = net.learn_one(x)
    assert d[m.winner] == d.min() and m.winner != m.runner_up
    A = net.edge_ages_
    assert np.array_equal(A, A.T) and np.all(np.diagonal(A) == -1)
    assert np.all((A >= 0).any(axis=1)), "no unit is left without an edge"
    ids = net.unit_ids_
    assert np.all(np.diff(ids) > 0) and ids.max() < net.next_unit_id_, "ids unique and increasing"
    kept = np.delete(ids_before, growth.removed)
    assert np.array_equal(ids[: len(kept)], kept) and len(ids) == len(kept) + growth.added
    assert net.weights_.shape[0] == len(ids) >= 2


@settings(max_examples=60, deadline=None)
@given(rows=streams, interval=st.integers(1, 4), max_age=st.integers(1, 4), seed=st.integers(0, 3))
def test_gng_invariants(rows, interval, max_age, seed):
    X = np.array(rows)
    net = GrowingNeuralGas(insertion_interval=interval, max_age=max_age, max_units=8)
    net.initialize(X, random_state=seed)
    for x in X:
        _learn_and_check(net, x)
        assert np.all(net.errors_ >= 0) and net.errors_.shape == (net.n_units_,)
        assert net.n_units_ <= 8


@settings(max_examples=60, deadline=None)
@given(rows=streams, a_t=st.floats(0.2, 1.0), h_t=st.floats(0.05, 1.0), max_age=st.integers(1, 4),
       seed=st.integers(0, 3))
def test_gwr_invariants(rows, a_t, h_t, max_age, seed):
    X = np.array(rows)
    net = GrowWhenRequired(activity_threshold=a_t, habituation_threshold=h_t, max_age=max_age)
    net.initialize(X, random_state=seed)
    for x in X:
        _learn_and_check(net, x)
        h = net.firing_.efficacy_
        assert h.shape == (net.n_units_,)
        assert np.all((h >= net.firing_.resting_efficacy - 1e-12) & (h <= 1.0))


def _random_graph(rng, n, max_age):
    """A symmetric age matrix over ``n`` units in which every unit has an edge, ages up to ``max_age``."""
    ages = np.full((n, n), -1, dtype=np.int32)
    order = rng.permutation(n)
    pairs = list(zip(order[:-1], order[1:]))
    pairs += [tuple(p) for p in rng.integers(0, n, size=(n, 2)) if p[0] != p[1]]
    for i, j in pairs:
        ages[i, j] = ages[j, i] = rng.integers(0, max_age + 1)
    return ages


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 9), max_age=st.integers(1, 3),
       network=st.sampled_from(["gng", "gwr"]))
def test_invariants_from_random_graphs(seed, n, max_age, network):
    """From any valid state, with old edges everywhere: removals keep the graph and the ids consistent."""
    rng = np.random.default_rng(seed)
    d = int(rng.integers(1, 4))
    state = {"weights_": rng.random((n, d)), "edge_ages_": _random_graph(rng, n, max_age),
             "unit_ids_": np.sort(rng.choice(100, size=n, replace=False)).astype(np.int64)}
    values = {"next_unit_id_": 100}
    if network == "gng":
        net = GrowingNeuralGas(max_age=max_age, insertion_interval=3, max_units=12)
        state["errors_"] = rng.random(n)
        values["n_inputs_"] = int(rng.integers(0, 3))
        children = {}
    else:
        net = GrowWhenRequired(max_age=max_age, activity_threshold=0.9, habituation_threshold=0.5)
        children = {"firing_": net._new_firing_counters().initialize(n)}
        children["firing_"].efficacy_[:] = rng.uniform(0.05, 1.0, size=n)
    net._import_state(state, values, children)
    for x in rng.random((15, d)):
        _learn_and_check(net, x)
