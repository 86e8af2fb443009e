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
import os
import signal
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sklearn.base import clone

import novelty
from novelty import _kernels
from novelty.clusterers.gwr import GrowWhenRequired
from novelty.filter import HabituatingFilter, learn_stream

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


@contextlib.contextmanager
def reference_only():
    """Make the filter use the reference loops (as when no kernel exists)."""
    learner, scorer = _kernels.learner, _kernels.scorer
    _kernels.learner = _kernels.scorer = lambda *args: None
    try:
        yield
    finally:
        _kernels.learner, _kernels.scorer = learner, scorer


def reference_learn(clusterer, synapse, X, dt, stimulus):
    """``learn_stream``, also returning the winner of each row."""
    winners = []
    match = clusterer.match

    def recording(x):
        m = match(x)
        winners.append(m.winner)
        return m

    clusterer.match = recording
    try:
        out = learn_stream(clusterer, synapse, X, dt, stimulus)
    finally:
        del clusterer.match
    return out, np.array(winners, dtype=np.int64)


def kernel_learn(clusterer, synapse, X, dt, stimulus):
    kernel = _kernels.learner(clusterer, synapse)
    assert kernel is not None
    winners = np.empty(X.shape[0], dtype=np.int64)
    out = kernel(clusterer, synapse, X, dt, stimulus, winners=winners)
    return out, winners


def assert_same_state(det_a, det_b):
    np.testing.assert_array_equal(det_a.clusterer_.weights_, det_b.clusterer_.weights_)
    np.testing.assert_array_equal(det_a.synapse_.efficacy_, det_b.synapse_.efficacy_)
    assert det_a.clusterer_.n_updates_ == det_b.clusterer_.n_updates_
    assert det_a.clusterer_._table_radius == det_b.clusterer_._table_radius


# ------------------------------------------------------------------ strategies
finite = dict(allow_nan=False, allow_infinity=False)

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
})


@st.composite
def stanley_params(draw):
    alpha = draw(st.floats(0.2, 3, **finite))
    method = draw(st.sampled_from(["euler", "exact"]))
    low = alpha if method == "euler" else 0.05  # Euler needs tau >= alpha
    tau = st.floats(low, 40, **finite)
    return {
        "alpha": alpha,
        "method": method,
        "tau_winner": draw(tau),
        "tau_neighbour": draw(tau),
        "y0": draw(st.floats(0.1, 3, **finite)),
        "others": draw(st.sampled_from(["hold", "forget"])),
        "tau_forget": draw(st.one_of(st.none(), tau)),
    }


@st.composite
def streams(draw):
    n_features = draw(st.integers(1, 40))
    n_samples = draw(st.integers(1, 60))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    scale = draw(st.sampled_from([1.0, 1e-3, 50.0]))
    X = rng.uniform(-scale, scale, size=(n_samples, n_features))
    if draw(st.booleans()):  # repeated scans make exact ties between units likely
        X = np.round(X, 1)
    if draw(st.booleans()):
        steps = rng.choice([0.0, 0.5, 1.0, 2.0, 3.7], size=n_samples)
        timestamps = np.cumsum(steps)
    else:
        timestamps = None
    return X, timestamps


#: the filter's novelty rules: the paper's, and habituation x mismatch with a
#: calibrated scale (short calibration, so that it ends within a stream) or a given one
rules = st.sampled_from([
    {},
    {"novelty_rule": "mismatch", "calibration_scans": 7},
    {"novelty_rule": "mismatch", "match_scale": 0.3},
])


def build(som, stanley, stimulus=1.0, seed=0, **rule):
    return HabituatingFilter.from_params("som", "stanley", stimulus=stimulus, random_state=seed,
                                         **som, **{f"synapse__{k}": v for k, v in stanley.items()},
                                         **rule)


# ------------------------------------------------------------------ learning
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(som=som_params, stanley=stanley_params(), data=streams(),
       stimulus=st.floats(0, 2, **finite))
def test_learning_equals_reference(som, stanley, data, stimulus):
    X, timestamps = data
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
    assert_same_state(fast, slow)


def corridor(n_scans, n_features=16, seed=0):
    """A smooth random walk in [0, 1]^n_features, like sonar scans along corridors."""
    rng = np.random.default_rng(seed)
    X = np.empty((n_scans, n_features))
    x = rng.uniform(0.2, 0.8, n_features)
    for i in range(n_scans):
        x = np.clip(x + rng.normal(0, 0.03, n_features), 0.0, 1.0)
        X[i] = x
    return X


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
    assert_same_state(fast, slow)
    # the learned map scores the corridor (and new scans) the same way
    probe = np.concatenate([X[::7], corridor(500, seed=1)])
    with reference_only():
        expected_scores = slow.novelty(probe)
    np.testing.assert_array_equal(fast.novelty(probe), expected_scores)


# ---------------------------------------------------------- growing networks
def assert_same_network(a, b):
    """Every piece of learned state of two growing networks (and their synapse banks) is equal."""
    for name in ("weights_", "edge_ages_", "unit_ids_", "errors_"):
        if hasattr(b.clusterer_, name):
            got, expected = getattr(a.clusterer_, name), getattr(b.clusterer_, name)
            assert got.dtype == expected.dtype, name
            np.testing.assert_array_equal(got, expected, err_msg=name)
    for name in ("next_unit_id_", "n_inputs_"):
        assert getattr(a.clusterer_, name, None) == getattr(b.clusterer_, name, None), name
    if hasattr(b.clusterer_, "firing_"):
        np.testing.assert_array_equal(a.clusterer_.firing_.efficacy_, b.clusterer_.firing_.efficacy_)
        assert a.clusterer_.activity_threshold_ == b.clusterer_.activity_threshold_
    np.testing.assert_array_equal(a.synapse_.efficacy_, b.synapse_.efficacy_)
    assert a.match_scale_ == b.match_scale_


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
                             stimulus=draw(st.floats(0, 2, **finite)),
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


# ------------------------------------------------------------------- scoring
@pytest.mark.parametrize("n_features", [1, 3, 7, 8, 9, 16, 24, 64, 127, 128, 129, 200, 300])
def test_distances_follow_numpy_summation(n_features):
    """The kernel's squared distances equal ``((W - x) ** 2).sum(axis=1)`` bit for bit."""
    rng = np.random.default_rng(n_features)
    W = rng.uniform(-1, 1, (13, n_features)) * rng.choice([1e-3, 1.0, 1e3], (13, n_features))
    X = rng.uniform(-1, 1, (20, n_features))
    module = _kernels._SOM.wait()
    rows, novelty_out, dist = np.empty(20, dtype=np.int64), np.empty(20), np.empty(20)
    params = np.zeros(len(module.PARAMS))
    params[0] = 13  # n_columns
    module.som_stanley_stream(W, np.arange(13.0), X, np.empty(0), rows, novelty_out, dist,
                              module.pairwise_plan(n_features), params, False, 0, 0)
    for i, x in enumerate(X):
        d = ((W - x) ** 2).sum(axis=1)
        assert rows[i] == np.argmin(d)
        assert dist[i] == d[rows[i]]
        assert novelty_out[i] == rows[i]


@settings(max_examples=40, deadline=None)
@given(som=som_params, data=streams(), n_test=st.integers(1, 300))
def test_batch_scoring_equals_score_one(som, data, n_test):
    X, _ = data
    det = build(som, {}).fit(X)
    rng = np.random.default_rng(n_test)
    probe = np.concatenate([X, rng.uniform(X.min(), X.max() + 1e-9, (n_test, X.shape[1]))])
    batch = det.novelty(probe)
    np.testing.assert_array_equal(batch, [det.score_one(x) for x in probe])
    with reference_only():
        np.testing.assert_array_equal(batch, det.novelty(probe))


@pytest.mark.parametrize("rule", ["efficacy", "mismatch"])
@pytest.mark.parametrize("clusterer", [
    "gng", "gwr", "online-kmeans",
    GrowWhenRequired(activity_threshold="auto", firing_condition=False, new_unit_wins=True),
])
def test_other_networks_batch_scoring_equals_reference(clusterer, rule):
    """The scoring kernel serves every clusterer whose winner is the nearest unit."""
    det = HabituatingFilter(clusterer=clusterer, novelty_rule=rule).fit(corridor(1500))
    assert _kernels.scorer(det.clusterer_, det.synapse_) is not None
    probe = np.concatenate([corridor(300, seed=3), np.round(corridor(200, seed=4), 1)])
    got = det.novelty(probe)
    np.testing.assert_array_equal(got, [det.score_one(x) for x in probe])
    with reference_only():
        np.testing.assert_array_equal(got, det.novelty(probe))
        np.testing.assert_array_equal(got, [det.score_one(x) for x in probe])


# ----------------------------------------------------------------- dispatch
def test_other_components_use_the_reference():
    class MySOM(novelty.SOM):
        pass

    det = HabituatingFilter(clusterer=MySOM(n_rows=2, n_columns=2)).fit(np.zeros((3, 2)))
    assert _kernels.learner(det.clusterer_, det.synapse_) is None
    hsom = novelty.make("hsom").fit(np.zeros((3, 2)))
    assert _kernels.learner(hsom.clusterer_, hsom.synapse_) is not None
    hsom.clusterer_.weights_ = np.asfortranarray(hsom.clusterer_.weights_)
    assert _kernels.learner(hsom.clusterer_, hsom.synapse_) is None


def test_missing_numba_falls_back_with_one_warning(monkeypatch):
    monkeypatch.setattr(_kernels, "_SOM", _kernels._Compiled("_som_stanley"))
    monkeypatch.delitem(sys.modules, "novelty._kernels._som_stanley")
    monkeypatch.delattr(_kernels, "_som_stanley", raising=False)
    monkeypatch.setitem(sys.modules, "numba", None)  # makes "import numba" fail
    X = corridor(50)
    det = novelty.make("hsom")
    with pytest.warns(RuntimeWarning, match="reference numpy loops"):
        assert _kernels.wait() is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = np.append(det.stream(X), det.score_learn_one(X[0]))
    with reference_only():
        ref = novelty.make("hsom")
        expected = np.append(ref.stream(X), ref.score_learn_one(X[0]))
    np.testing.assert_array_equal(got, expected)


def test_learning_hands_over_to_the_kernel_mid_stream(monkeypatch):
    """While the kernel compiles, the reference learns; the kernel takes over when ready."""
    monkeypatch.setattr(_kernels, "_HANDOVER_BLOCK", 100)
    module = _kernels._SOM.module
    calls = []

    def reference_blocks(som, syn, X, dt, stimulus, distances=None):
        calls.append(len(X))
        if len(calls) == 3:
            monkeypatch.setattr(_kernels._SOM, "module", module)  # "compiled" after 3 blocks
        return learn_stream(som, syn, X, dt, stimulus, distances=distances)

    monkeypatch.setattr(_kernels._SOM, "module", None)
    monkeypatch.setattr("novelty.filter.learn_stream", reference_blocks)
    X = corridor(1000)
    det = novelty.make("hsom").fit(X[:1])
    assert _kernels.learner(det.clusterer_, det.synapse_) is _kernels._som_handing_over
    calls.clear()
    got = det.stream(X)
    assert calls == [100, 100, 100]
    monkeypatch.undo()
    with reference_only():
        ref = novelty.make("hsom").fit(X[:1])
        expected = ref.stream(X)
    np.testing.assert_array_equal(got, expected)
    assert_same_state(det, ref)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork()")
def test_a_child_forked_while_compiling_compiles_for_itself(monkeypatch):
    monkeypatch.setattr(_kernels, "_SOM", _kernels._Compiled("_som_stanley"))
    blocker = threading.Event()
    _kernels._SOM.started = True  # "compiling" in the parent
    _kernels._SOM.thread = threading.Thread(target=blocker.wait)
    _kernels._SOM.thread.start()
    try:
        pid = os.fork()
        if pid == 0:  # the child: its compiler thread is gone; it must start one and get the kernel
            ok = _kernels._SOM.wait(timeout=60) is not None
            os._exit(0 if ok else 1)
        _, status = os.waitpid(pid, 0)
        assert os.waitstatus_to_exitcode(status) == 0
    finally:
        blocker.set()


def test_read_only_and_strided_inputs():
    X = corridor(300)
    det, ref = novelty.make("hsom"), novelty.make("hsom")
    frozen = X.copy()
    frozen.setflags(write=False)
    with reference_only():
        expected = np.concatenate([ref.stream(X), ref.novelty(X), [ref.score_one(X[:, 0][:16])]])
    got = np.concatenate([det.stream(frozen), det.novelty(frozen),
                          [det.score_one(np.asfortranarray(X)[:, 0][:16])]])
    np.testing.assert_array_equal(got, expected)


def test_import_novelty_does_not_import_numba():
    code = ("import sys, numpy as np, novelty\n"
            "det = novelty.make('hsom')\n"
            "assert 'numba' not in sys.modules\n"
            "det.fit(np.zeros((2, 3)))\n"
            "novelty._kernels.wait()\n"
            "assert 'numba' in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True)


def _plant_numba(folder):
    """A ``numba.py`` in ``folder`` that leaves a mark when imported, then fails the import."""
    mark = folder / "planted-numba-ran"
    (folder / "numba.py").write_text(f"open({str(mark)!r}, 'w').close()\nraise ImportError('planted')\n")
    return mark


def _script(tmp_path, code: str):
    """``code`` as a script file outside the working directory: its folder, not the cwd, leads sys.path."""
    folder = tmp_path / "script"
    folder.mkdir()
    path = folder / "main.py"
    path.write_text(code)
    return path


def test_the_background_compiler_ignores_the_working_directory(tmp_path):
    cwd, cache = tmp_path / "cwd", tmp_path / "cold-cache"
    cwd.mkdir()
    mark = _plant_numba(cwd)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    # The plant works: a plain child started in that folder runs it.
    subprocess.run([sys.executable, "-c", "import numba"], cwd=cwd, env=env, capture_output=True)
    assert mark.exists()
    mark.unlink()
    # The library's compiler child does not (a module that imports numba, compiles nothing).
    script = _script(tmp_path, "from novelty import _kernels\n"
                               "compiled = _kernels._Compiled('_distances')\n"
                               "assert compiled.wait(timeout=120) is not None, compiled.error\n")
    subprocess.run([sys.executable, str(script)], cwd=cwd, env=env, check=True, timeout=180)
    assert not mark.exists()


def test_ctrl_c_while_waiting_at_exit_for_the_compiler_exits_130_quietly(tmp_path):
    script = _script(tmp_path, "import sys\n"
                               "from novelty import _kernels\n"
                               "assert _kernels._Compiled('_som_stanley').get() is None\n"
                               "print('compiling', flush=True)\n")  # then exit: waits for the compiler
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cold-cache"))
    proc = subprocess.Popen([sys.executable, str(script)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            # a run in the background ignores SIGINT, and children inherit that
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        assert proc.stdout.readline() == "compiling\n"
        time.sleep(1.0)  # at exit, in the wait; a cold compile takes several seconds
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C reaches the whole foreground group
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130
    assert "Traceback" not in err and "Exception ignored" not in err


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
def test_hot_path_bounds_scans_and_rejects_nan():
    det = novelty.make("hsom").fit(np.zeros((2, 4)))
    large = np.full(4, 4.9e99)  # norm 9.8e99, just within the bound
    assert det.score_one(large) == det.novelty(large[None, :])[0]
    with pytest.raises(ValueError, match=r"norm above 1e\+100"):
        det.score_one(np.full(4, 1e308))  # finite, but squared distances overflow
    with pytest.raises(ValueError, match="NaN or infinity"):
        det.score_one(np.array([0.0, np.nan, 0.0, 0.0]))
    with pytest.raises(ValueError, match="NaN or infinity"):
        det.learn_one(np.array([0.0, np.inf, 0.0, 0.0]))


def test_a_som_with_its_own_neighbour_rate_learns_by_the_reference_loop():
    """The kernel shares one rate between winner and neighbours; the option (ours) takes the reference."""
    X = np.random.default_rng(0).random((50, 4))
    paper = novelty.make("hsom", n_rows=3, n_columns=3).fit(X)
    own = novelty.make("hsom", n_rows=3, n_columns=3, neighbour_learning_rate=0.25).fit(X)
    assert _kernels.learner(own.clusterer_, own.synapse_) is None
    np.testing.assert_array_equal(paper.clusterer_.weights_, own.clusterer_.weights_)
    np.testing.assert_array_equal(paper.synapse_.efficacy_, own.synapse_.efficacy_)


# ------------------------------------------------- long gaps, extreme scans
#: elapsed times from one scan to the next: ordinary, just beyond the sub-steps
#: iterated one by one, a time column in nanoseconds, and far beyond an int64
GAPS = [1.0, 1.0, 3.5, 1024.0, 1025.0, 1.0, 1e10, 1.0, 1e19, 2.0, 1e300, 1.0]


@pytest.mark.parametrize("name", ["hsom", "gng-stanley", "gwr-novelty"])
@pytest.mark.parametrize("params", [{}, {"synapse__others": "forget"}])
def test_long_gaps_kernel_equals_reference_and_efficacy_stays_in_range(name, params):
    X = np.random.default_rng(5).uniform(size=(len(GAPS), 4))
    timestamps = np.cumsum(GAPS)
    fast, slow = novelty.make(name, **params), novelty.make(name, **params)
    _kernels.wait()
    got = fast.stream(X, timestamps=timestamps)
    with reference_only():
        expected = slow.stream(X, timestamps=timestamps)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(fast.synapse_.efficacy_, slow.synapse_.efficacy_)
    y = fast.synapse_.efficacy_
    assert np.all((y >= fast.resting_novelty) & (y <= 1.0))


@pytest.mark.parametrize("name", ["gwr-novelty", "gng-stanley", "hsom"])
def test_scans_at_the_norm_bound_kernel_equals_reference(name):
    X = np.random.default_rng(6).normal(size=(60, 4))
    X *= 0.99e100 / np.linalg.norm(X, axis=1, keepdims=True)  # as far apart as allowed
    fast, slow = novelty.make(name), novelty.make(name)
    _kernels.wait()
    got = fast.stream(X)
    with reference_only():
        expected = slow.stream(X)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(fast.clusterer_.weights_, slow.clusterer_.weights_)
    assert np.all(np.isfinite(fast.clusterer_.weights_))
    if name != "hsom":
        assert_same_network(fast, slow)
