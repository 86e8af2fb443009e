"""The compiled kernels (novelty._kernels) against the readable reference.

The reference is ``learn_stream`` with ``SOM.match`` / ``SOM.adapt`` and
``StanleySynapse.step`` (learning) and ``Clusterer.winners`` (scoring). The
kernels repeat numpy's floating-point operations in numpy's order, so every
comparison here is exact equality, not a tolerance. No timing is asserted
(``benchmarks/perf.py`` measures speed).
"""

from __future__ import annotations

import contextlib
import copy

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sklearn.base import clone

import novelty
from novelty import _kernels, registry
from novelty.clusterers.base import Clusterer
from novelty.filter import HabituatingFilter

from tests.damaged import damaging

from .kernel_helpers import (assert_same_filter, assert_same_state, both, corridor, finite,
                            kernel_learn, reference_learn, reference_only, rules, streams,
                            within_fixed_point)

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


def assert_same_som(det_a, det_b):
    assert_same_filter(det_a, det_b)


som_params = st.fixed_dictionaries({
    "n_rows": st.integers(1, 6),
    "n_columns": st.integers(1, 6),
    "learning_rate": st.floats(0, 1, **finite),
    "radius": st.one_of(st.integers(0, 4), st.floats(0, 4.5, **finite)),
    "decay": st.sampled_from(["constant", "linear", "asymptotic"]),
    "decay_steps": st.integers(1, 40),
    "learning_rate_final": st.floats(0, 1, **finite),
    "radius_final": st.floats(0, 3, **finite),
    "init": st.sampled_from(["uniform", "sample"]),
    "neighbour_learning_rate": st.one_of(st.none(), st.floats(0, 1, **finite)),
})


@st.composite
def stanley_params(draw):
    # y0 <= 1 and alpha y0 >= 1: the efficacy stays in [0, 1] under the default stimulus S = 1
    alpha = draw(st.floats(1, 3, **finite))
    method = draw(st.sampled_from(["euler", "exact"]))
    low = alpha if method == "euler" else 0.05  # Euler needs tau >= alpha
    tau = st.floats(low, 40, **finite)
    return {
        "alpha": alpha,
        "method": method,
        "tau_winner": draw(tau),
        "tau_neighbour": draw(tau),
        "y0": draw(st.floats(1 / alpha, 1, **finite)),
        "others": draw(st.sampled_from(["hold", "forget"])),
        "tau_forget": draw(st.one_of(st.none(), tau)),
    }


def build(som, stanley, stimulus=1.0, seed=0, **rule):
    return HabituatingFilter.from_params("som", "stanley", stimulus=stimulus, random_state=seed,
                                         **som, **{f"synapse__{k}": v for k, v in stanley.items()},
                                         **rule)


# ------------------------------------------------------------------ learning
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(som=som_params, stanley=stanley_params(), data=streams(),
       stimulus=st.floats(0, 1, **finite))
def test_learning_equals_reference(som, stanley, data, stimulus):
    X, timestamps = data
    stimulus = within_fixed_point(stimulus, stanley["alpha"], stanley["y0"])
    det = build(som, stanley, stimulus)
    det._validate_params()
    det._begin(X)
    dt = det._elapsed(X.shape[0], timestamps)
    ref_c, ref_s = copy.deepcopy(det.clusterer_), copy.deepcopy(det.synapse_)

    expected, expected_winners = reference_learn(ref_c, ref_s, X, dt, float(stimulus))
    got, winners = kernel_learn(det.clusterer_, det.synapse_, X, dt, float(stimulus))

    np.testing.assert_array_equal(winners, expected_winners)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(det.clusterer_.weights_, ref_c.weights_)
    np.testing.assert_array_equal(det.synapse_.efficacy_, ref_s.efficacy_)
    assert det.clusterer_.n_updates_ == ref_c.n_updates_
    assert det.clusterer_._table_radius == ref_c._table_radius


@settings(max_examples=40, deadline=None)
@given(som=som_params, stanley=stanley_params(), data=streams(), split=st.integers(0, 60),
       rule=rules)
def test_detector_api_equals_reference(som, stanley, data, split, rule):
    """fit / partial_fit / score_learn_one / novelty / score_one, kernel vs reference, every rule."""
    X, _ = data
    fast, slow = build(som, stanley, **rule), build(som, stanley, **rule)
    head, tail = X[:split], X[split:]
    results = []
    for det, context in ((fast, contextlib.nullcontext()), (slow, reference_only())):
        with context:
            out = [det.stream(head)] if len(head) else []
            out.append(np.array([det.score_learn_one(x) for x in tail[:5]]))
            if len(tail) > 5:
                out.append(det.stream(tail[5:]))
            out.append(det.novelty(X))
            out.append(np.array([det.score_one(x) for x in X]))
            results.append(np.concatenate(out))
    np.testing.assert_array_equal(results[0], results[1])
    assert_same_som(fast, slow)


@pytest.mark.parametrize("synapse", [
    {},  # the paper's configuration
    {"synapse__others": "forget", "synapse__tau_forget": 60.0},
    {"synapse__method": "exact", "synapse__others": "forget"},
])
@pytest.mark.parametrize("som", [{}, {"decay": "linear", "radius": 3, "decay_steps": 1500}])
def test_corridor_stream_equals_reference(som, synapse):
    X = corridor(3000)
    fast, slow = novelty.make("hsom", **som, **synapse), novelty.make("hsom", **som, **synapse)
    got = np.concatenate([fast.stream(X[:10]), fast.stream(X[10:])])
    with reference_only():
        expected = np.concatenate([slow.stream(X[:10]), slow.stream(X[10:])])
    np.testing.assert_array_equal(got, expected)
    assert_same_som(fast, slow)
    # the learned map scores the corridor (and new scans) the same way
    probe = np.concatenate([X[::7], corridor(500, seed=1)])
    with reference_only():
        expected_scores = slow.novelty(probe)
    np.testing.assert_array_equal(fast.novelty(probe), expected_scores)


# ---------------------------------------------------------- growing networks
assert_same_network = assert_same_filter


gng_params = st.fixed_dictionaries({
    "epsilon_b": st.floats(0, 1, **finite),
    "epsilon_n": st.floats(0, 1, **finite),
    "insertion_interval": st.integers(1, 20),
    "insertion_error_decay": st.floats(0, 1, **finite),
    "error_decay": st.floats(0, 1, **finite),
    "max_age": st.integers(1, 8),
    "max_units": st.integers(2, 12),
    "init": st.sampled_from(["sample", "uniform"]),
})

gwr_params = st.fixed_dictionaries({
    "activity_threshold": st.one_of(st.floats(0, 1, **finite), st.just("auto")),
    "firing_condition": st.booleans(),
    "new_unit_wins": st.booleans(),
    "habituation_threshold": st.floats(0, 1.2, **finite),
    "epsilon_b": st.floats(0, 1, **finite),
    "epsilon_n": st.floats(0, 1, **finite),
    "max_age": st.integers(1, 8),
    "max_units": st.one_of(st.none(), st.integers(2, 12)),
    "init": st.sampled_from(["sample", "uniform"]),
})


@st.composite
def growing_filters(draw):
    kind = draw(st.sampled_from(["gng", "gwr"]))
    params = draw(gng_params if kind == "gng" else gwr_params)
    if kind == "gwr":
        firing = draw(stanley_params())
        params["firing"] = novelty.StanleySynapse(**firing)
    synapse = novelty.StanleySynapse(**draw(stanley_params()))
    clusterer = novelty.registry.clusterers.make(kind, **params)
    return HabituatingFilter(clusterer=clusterer, synapse=synapse,
                             stimulus=within_fixed_point(draw(st.floats(0, 1, **finite)), synapse.alpha,
                                                         synapse.y0),
                             random_state=draw(st.integers(0, 100)), **draw(rules))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(det=growing_filters(), data=streams(), split=st.integers(0, 60))
def test_growing_networks_equal_reference(det, data, split):
    X, timestamps = data
    fast, slow = clone(det), clone(det)
    results = []
    for model, context in ((fast, contextlib.nullcontext()), (slow, reference_only())):
        with context:
            t = None if timestamps is None else timestamps[:split]
            out = [model.stream(X[:split], timestamps=t)] if split else []
            if split < len(X):
                t = None if timestamps is None else timestamps[split:]
                out.append(model.stream(X[split:], timestamps=t))
            out.append(np.array([model.score_learn_one(x) for x in X[:3]]))
            out.append(model.novelty(X))
            results.append(np.concatenate(out))
    np.testing.assert_array_equal(results[0], results[1])
    assert_same_network(fast, slow)


@pytest.mark.parametrize("name,params", [
    ("gng-stanley", {}),
    ("gng-stanley", {"insertion_interval": 10, "max_age": 4, "synapse__others": "forget"}),
    ("gwr-novelty", {}),
    ("gwr-novelty", {"activity_threshold": 0.95, "max_age": 3, "synapse__method": "exact"}),
    ("gwr-novelty", {"activity_threshold": "auto", "firing_condition": False, "new_unit_wins": True,
                     "novelty_rule": "mismatch"}),
    ("gng-stanley", {"insertion_interval": 10, "novelty_rule": "mismatch"}),
    ("gwr-explore", {}),
])
def test_growing_corridor_equals_reference(name, params):
    X = corridor(3000)
    fast, slow = novelty.make(name, **params), novelty.make(name, **params)
    got = np.concatenate([fast.stream(X[:10]), fast.stream(X[10:])])
    with reference_only():
        expected = np.concatenate([slow.stream(X[:10]), slow.stream(X[10:])])
    np.testing.assert_array_equal(got, expected)
    assert_same_network(fast, slow)
    assert fast.clusterer_.next_unit_id_ > 2  # units were added (and, with max_age 3, deleted)


# ------------------------------------------------- long gaps, extreme scans
#: elapsed times from one scan to the next: ordinary, just beyond the sub-steps
#: iterated one by one, a time column in nanoseconds, and far beyond an int64
GAPS = [1.0, 1.0, 3.5, 1024.0, 1025.0, 1.0, 1e10, 1.0, 1e19, 2.0, 1e300, 1.0]


@pytest.mark.parametrize("name", ["hsom", "gng-stanley", "gwr-novelty", "som-wang-hsu"])
@pytest.mark.parametrize("params", [{}, {"synapse__others": "forget"}])
def test_long_gaps_kernel_equals_reference_and_efficacy_stays_in_range(name, params):
    X = np.random.default_rng(5).uniform(size=(len(GAPS), 4))
    timestamps = np.cumsum(GAPS)
    fast, slow = novelty.make(name, **params), novelty.make(name, **params)
    got = fast.stream(X, timestamps=timestamps)
    with reference_only():
        expected = slow.stream(X, timestamps=timestamps)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(fast.synapse_.efficacy_, slow.synapse_.efficacy_)
    y = fast.synapse_.efficacy_
    if name == "som-wang-hsu":  # recovered to y0 within rounding
        fast.synapse_.check_efficacy(1.0)
    else:
        assert np.all((y >= fast.resting_novelty) & (y <= 1.0))


@pytest.mark.parametrize("name", ["gwr-novelty", "gng-stanley", "hsom"])
def test_scans_at_the_norm_bound_kernel_equals_reference(name):
    X = np.random.default_rng(6).normal(size=(60, 4))
    X *= 0.99e100 / np.linalg.norm(X, axis=1, keepdims=True)  # as far apart as allowed
    fast, slow = novelty.make(name), novelty.make(name)
    got = fast.stream(X)
    with reference_only():
        expected = slow.stream(X)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(fast.clusterer_.weights_, slow.clusterer_.weights_)
    assert np.all(np.isfinite(fast.clusterer_.weights_))
    if name != "hsom":
        assert_same_network(fast, slow)


# ------------------------------------------------------- every registered pair
@st.composite
def synapse_options(draw, name):
    """Options of a registered synapse that change its arithmetic (Euler needs slow taus)."""
    method = draw(st.sampled_from(["euler", "exact"]))
    options = {"method": method, "others": draw(st.sampled_from(["hold", "forget"])),
               "tau_forget": draw(st.one_of(st.none(), st.floats(6.0, 40, **finite)))}
    if name == "staddon-higa":  # one discretisation only: the difference equation
        del options["method"]
        options.update(fast_gain=draw(st.floats(0.05, 1, **finite)), slow_gain=draw(st.floats(0, 2, **finite)),
                       slowness=draw(st.floats(1, 40, **finite)),
                       tau_winner=draw(st.floats(1, 30, **finite)))
    elif name == "wang-hsu":
        options["beta"] = draw(st.floats(0, 2, **finite))
        options["gamma"] = draw(st.floats(0, 0.5, **finite))
        options["tau_winner"] = draw(st.floats(3.1 if method == "euler" else 0.5, 30, **finite))
    else:
        options["tau_winner"] = draw(st.floats(1.05 if method == "euler" else 0.1, 30, **finite))
    return options


def _declares_kernel(registry_, name) -> bool:
    return "_kernel" in vars(type(registry_.make(name)))


# Registered components that declare compiled steps (the package's own; a plugin's
# when it does) must equal the reference (the others run it: test_choice). A map's world
# cells (several winners a scan) compose in a map, checked by its conformance checks.
CLUSTERERS = [n for n in registry.clusterers.names() if _declares_kernel(registry.clusterers, n)
              and isinstance(registry.clusterers.make(n), Clusterer)]
SYNAPSES = [n for n in registry.synapses.names() if _declares_kernel(registry.synapses, n)]


@pytest.mark.parametrize("synapse_name", SYNAPSES)
@pytest.mark.parametrize("clusterer_name", CLUSTERERS)
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), stream=streams(max_features=20), stimulus=st.floats(0, 1, **finite))
def test_every_registered_pair_equals_reference(clusterer_name, synapse_name, data, stream,
                                                stimulus):
    """States, winners, distances and novelty after a stream (growth and removal included)."""
    X, timestamps = stream
    options = data.draw(synapse_options(synapse_name))
    clusterer = registry.clusterers.make(clusterer_name)
    if clusterer_name in ("gng", "gwr"):
        clusterer.set_params(max_age=data.draw(st.integers(1, 6)))
    if clusterer_name == "gng":
        clusterer.set_params(insertion_interval=data.draw(st.integers(1, 10)))
    if clusterer_name == "online-kmeans":
        init = data.draw(st.sampled_from(["sample", "first"]))
        clusterer.set_params(init=init, n_clusters=data.draw(st.integers(1, 8)),
                             placement_radius=data.draw(st.sampled_from([0.0, 0.5, 2.0]))
                             if init == "first" else 0.0)
    if clusterer_name == "gwr":
        clusterer.set_params(activity_threshold=data.draw(st.floats(0, 1, **finite)),
                             new_unit_wins=data.draw(st.booleans()),
                             firing_condition=data.draw(st.booleans()))
    synapse = registry.synapses.make(synapse_name, **options)
    clusterer.initialize(X, data.draw(st.integers(0, 10)))
    synapse.initialize(clusterer.n_units_)
    dt = np.ones(len(X)) if timestamps is None else np.diff(timestamps, prepend=timestamps[0])
    (fast_c, fast_s), (slow_c, slow_s) = both(clusterer, synapse)
    d_fast, d_slow = np.empty(len(X)), np.empty(len(X))
    expected, expected_winners = reference_learn(slow_c, slow_s, X, dt, stimulus, d_slow)
    got, winners = kernel_learn(fast_c, fast_s, X, dt, stimulus, d_fast)
    np.testing.assert_array_equal(winners, expected_winners)
    np.testing.assert_array_equal(d_fast, d_slow)
    assert_same_state(fast_c, slow_c)
    if synapse_name == "wang-hsu" and options["method"] == "exact":
        # exp and log: numpy's own (SIMD) in the reference, the C library's compiled; they
        # may differ in the last bit, so the synapses agree to rounding, not bit for bit
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-300)
        for name in ("efficacy_", "recovery_"):
            np.testing.assert_allclose(getattr(fast_s, name), getattr(slow_s, name), rtol=1e-12,
                                       atol=1e-300)
    else:
        np.testing.assert_array_equal(got, expected)
        assert_same_state(fast_s, slow_s)


def test_the_package_compiles_every_component_it_registers():
    for registry_ in (registry.clusterers, registry.synapses):
        own = [n for n in registry_.names()
               if registry_.get(n).__module__.startswith("novelty.")]
        assert own and all(_declares_kernel(registry_, n) for n in own), registry_.kind


@pytest.mark.parametrize("n_features", [1, 3, 7, 8, 9, 16, 24, 64, 127, 128, 129, 200, 300])
def test_distances_follow_the_projects_order(n_features):
    """The drivers' squared distances equal ``novelty.distances.squared_distances`` bit for bit."""
    rng = np.random.default_rng(n_features)
    X = rng.uniform(-1, 1, (40, n_features)) * rng.choice([1e-3, 1.0, 1e3], (40, n_features))
    clusterer = registry.clusterers.make("online-kmeans", n_clusters=13).initialize(X, 0)
    synapse = registry.synapses.make("stanley").initialize(13)
    (fast_c, fast_s), (slow_c, slow_s) = both(clusterer, synapse)
    d_fast, d_slow = np.empty(len(X)), np.empty(len(X))
    expected, expected_winners = reference_learn(slow_c, slow_s, X, np.ones(len(X)), 1.0, d_slow)
    got, winners = kernel_learn(fast_c, fast_s, X, np.ones(len(X)), 1.0, d_fast)
    np.testing.assert_array_equal(winners, expected_winners)
    np.testing.assert_array_equal(d_fast, d_slow)
    assert_same_state(fast_c, slow_c)


# ------------------------------------------- state or parameters changed between calls
def _set_weights(det):
    det.clusterer_.weights_ = det.clusterer_.weights_[::-1] * 0.5  # a new array (strided)


def _read_only_efficacy(det):
    if det.compiled_ == "compiled":  # the reference writes in place: it needs a writable one
        det.synapse_.efficacy_.flags.writeable = False


def _efficacy_in_place(det):
    det.synapse_.efficacy_[::2] = 0.25


def _learning_rate(det):
    det.clusterer_.learning_rate = 0.75


def _tau_winner(det):
    det.synapse_.set_params(tau_winner=7.5)


def _method_then_alpha(det):
    det.synapse_.method = "exact"
    det.synapse_.alpha = 2.0


def _counter(det):
    det.clusterer_.n_updates_ = 3


def _another_synapse(det):
    synapse = copy.deepcopy(det.synapse_)  # a copy of a fitted part is one
    with damaging((synapse,)):
        synapse.tau_neighbour = 20.0
    det.synapse_ = synapse


def _firing_counters(det):
    det.clusterer_.firing_.tau_winner = 9.0  # a nested component's parameter


def _activity_threshold(det):
    det.clusterer_.activity_threshold_ = 0.9


def _removed_unit_ids(det):
    det.clusterer_.unit_ids_ = det.clusterer_.unit_ids_ + 100
    det.clusterer_.next_unit_id_ += 100


CHANGES = [("hsom", {}, change) for change in (
    _set_weights, _read_only_efficacy, _efficacy_in_place, _learning_rate, _tau_winner,
    _method_then_alpha, _counter, _another_synapse)] + [
    ("gwr-novelty", {"calibration_scans": 10}, change) for change in (
        _firing_counters, _activity_threshold, _removed_unit_ids, _set_weights)]


@pytest.mark.parametrize("preset, params, change", CHANGES, ids=lambda v: getattr(v, "__name__", None))
def test_what_changed_between_two_compiled_calls_is_used(preset, params, change):
    """The checks and the packed parameters remembered from one call are not used once the
    state or a parameter changed: the next call equals the reference's, bit for bit."""
    X = corridor(120, n_features=5, seed=3)
    fast = novelty.make(preset, **params).fit(X[:10])
    assert _kernels.wait(fast.clusterer_, fast.synapse_) is not None
    slow = copy.deepcopy(fast)
    for block in (X[10:40], X[40:41], X[41:60]):  # compiled calls, remembered
        fast.partial_fit(block)
        with reference_only():
            slow.partial_fit(block)
    with damaging(fast):  # the state changed as nothing in the library may (tests.damaged)
        change(fast)
    with reference_only(), damaging(slow):
        change(slow)
    got = fast.stream(X[60:])
    with reference_only():
        expected = slow.stream(X[60:])
    np.testing.assert_array_equal(got, expected)
    assert_same_filter(fast, slow)


def test_the_components_show_the_engines_state():
    """The fitted parts' arrays are views of the engine's: learning is seen through an array
    read before it, and another engine of the same parts (asked for by wait) takes nothing away."""
    X = corridor(60, n_features=5, seed=7)
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(X[:10])
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None
    det.learn_one(X[10])
    weights, efficacy = det.clusterer_.weights_, det.synapse_.efficacy_
    det.learn_one(X[11])
    assert det.clusterer_.weights_ is weights and det.synapse_.efficacy_ is efficacy
    assert np.shares_memory(weights, det._engine._WT)
    before = weights.copy()
    det.partial_fit(X[12:20])
    assert not np.array_equal(weights, before)  # learned in place
    slow = copy.deepcopy(det)
    _kernels.wait(det.clusterer_, det.synapse_)  # another engine reads the parts
    det.partial_fit(X[20:40])
    for x in X[40:]:
        det.learn_one(x)
    with reference_only():
        slow.partial_fit(X[20:40])
        for x in X[40:]:
            slow.learn_one(x)
    assert_same_filter(det, slow)
    assert np.shares_memory(det.clusterer_.weights_, det._engine._WT)


def test_the_engines_room_is_whole_vectors_of_the_distance_loops():
    """The engine (which must not import numba) rounds its capacity up to the distance loops'
    vector, and the room past the units is zero."""
    from novelty._kernels import _distances, engine

    assert engine.VECTOR == _distances.VECTOR
    assert [engine.whole_vectors(n) for n in (1, 8, 9, 100)] == [8, 8, 16, 104]
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(20, n_features=5, seed=2))
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None
    det.learn_one(corridor(1, n_features=5, seed=3)[0])
    WT = det._engine._WT
    assert WT.shape == (5, 16) and det._engine.capacity == 16
    assert not WT[:, 9:].any() and not det._engine._s_arrays[0][9:].any()


def test_weights_written_in_place_are_what_the_next_compiled_call_reads():
    """The engine holds the weights transposed and ``weights_`` is a view of them: a unit
    moved by writing into that view (a row, one element) is where every next call finds it,
    learning scan by scan or in a block, and scoring one scan or a batch, as the reference."""
    X = corridor(80, n_features=5, seed=11)
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(X[:10])
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None
    det.learn_one(X[10])
    assert det._engine is not None and not det.clusterer_.weights_.flags.c_contiguous
    slow = copy.deepcopy(det)
    far = np.full(5, 0.9)
    for d in (det, slow):  # unit 4 moved onto the next scan, unit 7 far along feature 2
        with damaging(d):
            d.clusterer_.weights_[4] = X[11]
            d.clusterer_.weights_[7, 2] = 0.0
    assert det.clusterer_.weights_[4].tolist() == X[11].tolist()
    assert det.winners(X[11:12])[0][0] == det.clusterer_.unit_ids_[4]
    with reference_only():
        expected = [slow.score_one(X[11]), slow.score_learn_one(X[11]), slow.score_one(far)]
        slow.partial_fit(X[12:30])
        expected_batch = slow.score_samples(X[30:])
    assert [det.score_one(X[11]), det.score_learn_one(X[11]), det.score_one(far)] == expected
    det.partial_fit(X[12:30])
    assert det.score_samples(X[30:]).tolist() == expected_batch.tolist()
    assert_same_filter(det, slow)


@pytest.mark.parametrize("single", [False, True])
def test_a_growing_network_gets_room_to_grow(single):
    """Units added move the state into larger arrays only when the room is used up (at least
    doubling): a few moves for a network grown from 2 units to a hundred."""
    X = corridor(1500, n_features=3, seed=8) * np.array([40.0, 1.0, 1.0])
    det = novelty.make("gng-stanley", insertion_interval=5).fit(X[:2])
    slow = copy.deepcopy(det)
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None
    moves, capacity = 0, det._current_engine().capacity
    for block in np.array_split(X[2:], 50):
        if single:
            for x in block:
                det.learn_one(x)
        else:
            det.partial_fit(block)
        moves += det._engine.capacity != capacity
        capacity = det._engine.capacity
    with reference_only():
        slow.partial_fit(X[2:])
    assert_same_filter(det, slow)
    n = det.clusterer_.n_units_
    assert n >= 64 and capacity >= n and moves <= 8


@pytest.mark.parametrize("clusterer_name", CLUSTERERS)
def test_short_batches_scored_scan_by_scan_equal_the_batch_kernel(clusterer_name, monkeypatch):
    """The compiled engine scores a batch of at most FEW scans by the driver's score_one (one
    scan at a time, against the weights as learning holds them): winners, distances and
    efficacies equal the batch kernel's bit for bit, exact ties between two units included; a
    read-only batch, and a unit within the bound that the driver's cheaper check of the
    weights refuses, take the batch kernel, and so do strided scans (which the driver's
    signature does not take)."""
    from novelty._kernels import engine as engine_module
    from novelty._kernels.engine import CompiledEngine

    X = corridor(260, n_features=5, seed=3)
    det = HabituatingFilter(clusterer=clusterer_name).fit(X[:2])
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None and _kernels.wait() is not None
    det.stream(X[2:200])
    engine = det._current_engine()
    assert type(engine) is CompiledEngine and engine._score_one is not None
    W = det.clusterer_.weights_
    tie = (W[0] + W[-1]) / 2  # as far from the first unit as from the last (or nearly)
    batches = [X[200:201], X[201:203], np.stack([tie, W[-1]]), tie[None, :]]
    batch_kernel = engine_module._score_batch
    calls = []
    monkeypatch.setattr(engine_module, "_score_batch", lambda *a: calls.append(1) or batch_kernel(*a))
    assert engine_module.FEW >= 2
    for Q in batches:
        got = engine.score(Q)
        monkeypatch.setattr(engine_module, "FEW", 0)
        want = engine.score(Q)
        monkeypatch.undo()
        monkeypatch.setattr(engine_module, "_score_batch", lambda *a: calls.append(1) or batch_kernel(*a))
        for a, b in zip(got, want):
            np.testing.assert_array_equal(a, b)
    assert len(calls) == len(batches)  # the FEW = 0 calls only
    read_only = X[200:202].copy()
    read_only.setflags(write=False)
    engine.score(read_only)
    assert len(calls) == len(batches) + 1
    engine.score(X[200:204:2])  # strided rows
    engine.score(W[-1][None, :])  # a row of weights_, a transposed view: a strided scan
    assert len(calls) == len(batches) + 3
    far = X[203].copy()
    far[:] = 0.99999999e100 / np.sqrt(far.size)  # within the bound, beyond the driver's check from X
    with damaging(det):
        W[0] = far
    got = engine.score(X[204:205])
    assert len(calls) == len(batches) + 4
    monkeypatch.setattr(engine_module, "FEW", 0)
    for a, b in zip(got, engine.score(X[204:205])):
        np.testing.assert_array_equal(a, b)
