"""Batch scoring (novelty._kernels.scoring, ._nearest) against ``match``, exactly.

The reference for every scan ``x`` is what ``Clusterer.match`` computes:
``d = squared_distances(W, x)``, the winner ``np.argmin(d)`` (the first
unit of least distance) and its distance ``d[winner]``. The compiled path
must give the same winners and the same distances bit for bit, through its
float32 pre-filter (ordinary data) and its exact path (ties, near ties,
magnitudes the pre-filter cannot bound). No timing here: benchmarks/perf.py.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import novelty
from novelty import _kernels
from novelty._kernels import scoring
from novelty._validation import MAX_SCAN_NORM
from novelty.clusterers.gng import GrowingNeuralGas
from novelty.clusterers.gwr import GrowWhenRequired
from novelty.clusterers.kmeans import OnlineKMeans
from novelty.clusterers.som import SOM
from novelty.distances import squared_distances
from novelty.filter import HabituatingFilter

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


def reference(W, X):
    """``match``'s winners and distances, scan by scan."""
    rows, dist = [], []
    for x in X:
        d = squared_distances(W, x)
        j = int(np.argmin(d))
        rows.append(j)
        dist.append(d[j])
    return np.array(rows, dtype=np.int64), np.array(dist)


def compiled(W, X, y=None):
    """The compiled scoring: (novelty, winners, distances, scans that took the exact path)."""
    W, X = np.ascontiguousarray(W, dtype=float), np.ascontiguousarray(X, dtype=float)
    y = np.arange(W.shape[0], dtype=float) if y is None else y
    module = _kernels._NEAREST.wait()
    n = X.shape[0]
    rows, dist, out = np.empty(n, dtype=np.int64), np.empty(n), np.empty(n)
    n_exact = module.nearest(W, y, X, rows, out, dist)
    return out, rows, dist, n_exact


def assert_same_as_match(W, X):
    out, rows, dist, n_exact = compiled(W, X)
    expected_rows, expected_dist = reference(W, X)
    np.testing.assert_array_equal(rows, expected_rows)
    np.testing.assert_array_equal(dist, expected_dist)
    np.testing.assert_array_equal(out, rows.astype(float))  # y = arange: novelty = winner
    return n_exact


# ------------------------------------------------------------ random data
@pytest.mark.parametrize("n_units, n_features", [
    (100, 16), (1, 16), (1, 1), (7, 1), (3, 2), (25, 8), (13, 24), (10, 127), (10, 128),
    (10, 129), (13, 200), (5, 300),
])
@pytest.mark.parametrize("n_scans", [1, 15, 16, 300, 1000])
def test_random_data_equals_match(n_units, n_features, n_scans):
    rng = np.random.default_rng(n_units * 1000 + n_features + n_scans)
    W = rng.uniform(0, 1, (n_units, n_features))
    X = rng.uniform(0, 1, (n_scans, n_features))
    n_exact = assert_same_as_match(W, X)
    if n_scans >= 300 and n_features < 100:
        # ordinary data: the pre-filter decides (almost) every scan, so the test covers it
        assert n_exact < n_scans // 10


def test_a_trained_map_scores_its_corridor_as_match():
    X = np.clip(np.cumsum(np.random.default_rng(0).normal(0, 0.03, (5000, 16)), axis=0) + 0.5, 0, 1)
    det = novelty.make("hsom").fit(X)
    # its units crowd together: about 13% of the scans have near ties that the
    # pre-filter leaves to the exact re-check of the candidates
    n_checked = assert_same_as_match(det.clusterer_.weights_, X)
    assert 0 < n_checked < len(X) // 4


# ---------------------------------------------------- ties and near ties
def test_exact_ties_take_the_first_unit():
    # x = 0 is at squared distance 1 from +-e_k for every k: all tie
    n = 16
    W = np.concatenate([np.eye(n), -np.eye(n)])
    X = np.zeros((200, n))
    X[100:] = 0.25  # ties again, between pairs (w - x has the same squares)
    n_exact = assert_same_as_match(W, X)
    assert n_exact >= 100  # the pre-filter sees a gap of 0 and hands ties over
    _, rows, _, _ = compiled(W, X[:1])
    assert rows[0] == 0


def test_duplicate_units_take_the_first():
    rng = np.random.default_rng(1)
    base = rng.uniform(0, 1, (10, 16))
    W = np.concatenate([base, base, base[::-1]])  # every unit three times
    X = rng.uniform(0, 1, (500, 16))
    assert_same_as_match(W, X)
    _, rows, _, _ = compiled(W, X)
    assert rows.max() < 10  # the first copy wins


@pytest.mark.parametrize("n_features", [1, 5, 16, 129])
def test_units_one_ulp_apart(n_features):
    """Units that differ in the last bit of one coordinate; scans around them."""
    rng = np.random.default_rng(n_features)
    w = rng.uniform(0.1, 1, n_features)
    units = [w]
    for k in range(n_features):
        for direction in (np.inf, -np.inf):
            v = w.copy()
            v[k] = np.nextafter(v[k], direction)
            units.append(v)
    W = np.array(units)
    X = np.concatenate([
        W,  # each unit itself (distance 0 to it, a few ulp^2 to the others)
        W + np.spacing(W) * rng.integers(-3, 4, W.shape),
        w + rng.normal(0, 1e-12, (200, n_features)),
        w + rng.normal(0, 1e-3, (200, n_features)),
    ])
    assert_same_as_match(W, X)
    assert_same_as_match(W[::-1].copy(), X)


def test_near_ties_between_distinct_units():
    """Scans on the bisector of two units, nudged by a few ulp either way."""
    rng = np.random.default_rng(2)
    a, b = rng.uniform(0, 1, 16), rng.uniform(0, 1, 16)
    W = np.concatenate([[a, b], rng.uniform(3, 4, (20, 16))])
    mid = (a + b) / 2
    normal = (b - a) / np.linalg.norm(b - a)
    X = np.array([mid + t * normal for t in np.concatenate([
        np.arange(-20, 21) * 1e-17, np.arange(-20, 21) * 1e-9, np.arange(-20, 21) * 1e-6])])
    assert_same_as_match(W, X)


# ------------------------------------------------------------- magnitudes
@pytest.mark.parametrize("scale", [1e-300, 1e-150, 1e-40, 1e-20, 1e-15, 1e-5, 1e5, 1e17, 1e18,
                                   1e19, 1e50, 1e99])
def test_magnitudes_up_to_the_norm_bound(scale):
    rng = np.random.default_rng(3)
    W = rng.uniform(-1, 1, (30, 16)) * scale / 4  # norms below 4 * scale / 4 = scale
    X = rng.uniform(-1, 1, (600, 16)) * scale / 4
    n_exact = assert_same_as_match(W, X)
    if scale >= 1e19:  # beyond the pre-filter's range: all exact
        assert n_exact == 600
    if 1e-15 <= scale <= 1e5:  # squares far above float32 underflow: the pre-filter decides
        assert n_exact < 60


def test_scans_at_the_norm_bound():
    rng = np.random.default_rng(4)
    X = rng.normal(size=(300, 4))
    X *= 0.999 * MAX_SCAN_NORM / np.linalg.norm(X, axis=1, keepdims=True)
    W = X[:20] * rng.uniform(0, 1, (20, 1))  # prototypes: convex combinations with 0
    assert_same_as_match(W, X)


def test_mixed_magnitudes_in_one_batch():
    """Huge scans beside ordinary ones: each scan takes its own path."""
    rng = np.random.default_rng(5)
    W = rng.uniform(0, 1, (50, 16))
    X = rng.uniform(0, 1, (1000, 16))
    huge = np.arange(len(X)) % 7 == 0
    X[huge] *= 1e30
    X[(np.arange(len(X)) % 11 == 3) & ~huge] *= 1e-30
    n_exact = assert_same_as_match(W, X)
    assert huge.sum() <= n_exact < len(X) // 2


# ------------------------------------------------- the pre-filter's bound
def prefilter_values(W, X, general=False):
    """The compiled pre-filter's values ``S[j, b]`` for units ``W`` and one block of scans."""
    module = _kernels._NEAREST.wait()
    lanes = module.LANES
    Wm, wn, _ = module.weights32(np.ascontiguousarray(W, dtype=float))
    XT = np.zeros((W.shape[1], lanes), dtype=np.float32)
    XT[:, : len(X)] = X.T  # rounded to float32, as the kernel does
    S = np.empty((W.shape[0], lanes), dtype=np.float32)
    acc, s1, s2 = (np.empty(lanes, dtype=np.float32) for _ in range(3))
    arg = np.empty(lanes, dtype=np.int32)
    prefilter = module._prefilter if general or W.shape[1] != 16 else module._prefilter16
    prefilter(Wm, wn, XT, S, acc, s1, s2, arg)
    return S[:, : len(X)], s1[: len(X)], s2[: len(X)], arg[: len(X)]


@pytest.mark.parametrize("general", [False, True])
@pytest.mark.parametrize("n_features", [16, 5, 21])
@pytest.mark.parametrize("case", ["uniform", "offset", "signs", "subnormal", "tiny", "large"])
def test_prefilter_values_within_the_bound(case, n_features, general):
    """|s^_j - (|w_j|^2 - 2 x.w_j)| <= gamma_{n+4}(u) (|w_j|^2 + 2 |x| |w_j|) + A, the module
    docstring's bound, against exact rational arithmetic; and the least two and the first
    unit of the least are those of the values."""
    import math
    from fractions import Fraction

    from novelty._kernels._nearest import TINY32, U32

    rng = np.random.default_rng(n_features)
    W = rng.uniform(0, 1, (12, n_features))
    X = rng.uniform(0, 1, (128, n_features))
    if case == "offset":  # large common offset: the expanded form cancels
        W, X = W * 1e-3 + 1e3, X * 1e-3 + 1e3
    elif case == "signs":
        W, X = W - 0.5, X - 0.5
    elif case == "subnormal":  # products and sums below float32's smallest normal
        W, X = W * 1e-22, X * 1e-22
    elif case == "tiny":  # the values themselves subnormal in float32
        W, X = W * 1e-40, X * 1e-40
    elif case == "large":
        W, X = W * 1e17, X * 1e17
    X[:3] = W[:3]  # scans on units
    S, s1, s2, arg = prefilter_values(W, X, general)
    n = n_features
    gamma = (n + 4) * U32 / (1 - (n + 4) * U32)
    for b, x in enumerate(X):
        x_norm = math.sqrt(sum(Fraction(v) ** 2 for v in x))
        for j, w in enumerate(W):
            exact = sum(Fraction(v) ** 2 for v in w) - 2 * sum(Fraction(a) * Fraction(c)
                                                               for a, c in zip(x, w))
            w_norm = math.sqrt(sum(Fraction(v) ** 2 for v in w))
            r = x_norm + w_norm
            bound = (gamma * (w_norm ** 2 + 2 * x_norm * w_norm)
                     + 3 * TINY32 * (math.sqrt(n) * r + 2 * n + 2)) * (1 + 1e-9)  # the norms' rounding
            assert abs(Fraction(float(S[j, b])) - exact) <= Fraction(bound), (b, j)
        order = np.argsort(S[:, b], kind="stable")
        assert arg[b] == order[0] and s1[b] == S[order[0], b] and s2[b] == S[order[1], b]


# -------------------------------------------------------------- properties
@st.composite
def maps_and_scans(draw):
    n_features = draw(st.integers(1, 20))
    n_units = draw(st.integers(1, 12))
    exponent = draw(st.integers(-30, 30))
    elements = st.floats(-4, 4, allow_nan=False, allow_infinity=False)
    W = draw(hnp.arrays(np.float64, (n_units, n_features), elements=elements)) * 10.0**exponent
    if draw(st.booleans()):  # copies of units, and units one ulp from others
        picks = draw(st.lists(st.integers(0, n_units - 1), min_size=1, max_size=4))
        extra = W[picks].copy()
        if draw(st.booleans()):
            extra[:, 0] = np.nextafter(extra[:, 0], np.inf)
        W = np.concatenate([W, extra])
    X = draw(hnp.arrays(np.float64, (draw(st.integers(1, 40)), n_features), elements=elements))
    X = X * 10.0**exponent
    if draw(st.booleans()):  # scans on units
        X = np.concatenate([X, W[: draw(st.integers(1, W.shape[0]))]])
    repeat = draw(st.sampled_from([1, 5]))  # 5: enough scans for the pre-filter's lanes
    return W, np.tile(X, (repeat, 1))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=maps_and_scans())
def test_winners_and_distances_equal_match(case):
    W, X = case
    assert_same_as_match(W, X)


# ------------------------------------------------- through the detector
def corridor(n_scans, n_features=16, seed=0):
    steps = np.random.default_rng(seed).normal(0, 0.03, (n_scans, n_features))
    return np.clip(0.5 + np.cumsum(steps, axis=0), 0, 1)


@pytest.mark.parametrize("clusterer", [
    SOM(), GrowingNeuralGas(), GrowWhenRequired(), OnlineKMeans(),
    SOM(n_rows=1, n_columns=1), OnlineKMeans(n_clusters=100, init="first"),
])
@pytest.mark.parametrize("synapse", ["stanley", "wang-hsu"])
def test_every_nearest_unit_clusterer_scores_as_match(clusterer, synapse):
    det = HabituatingFilter(clusterer=clusterer, synapse=synapse).fit(corridor(1200))
    kernel = _kernels.scorer(det.clusterer_, det.synapse_)
    assert kernel is not None
    probe = np.concatenate([corridor(800, seed=3), np.round(corridor(400, seed=4), 1),
                            det.clusterer_.weights_])
    rows, dist = np.empty(len(probe), dtype=np.int64), np.empty(len(probe))
    got = kernel(det.clusterer_, det.synapse_, probe, rows, dist)
    matches = [det.clusterer_.match(x) for x in probe]
    np.testing.assert_array_equal(rows, [m.winner for m in matches])
    np.testing.assert_array_equal(dist, [m.distance for m in matches])
    np.testing.assert_array_equal(got, det.synapse_.efficacy_[rows])
    np.testing.assert_array_equal(det.novelty(probe), [det.score_one(x) for x in probe])


# ------------------------------------------------------------------ threads
def test_threads_give_the_same_result(monkeypatch):
    """Large batches are split across threads; the result does not depend on it."""
    det = novelty.make("hsom").fit(corridor(2000))
    probe = np.random.default_rng(0).uniform(0, 1, (10_007, 16))
    monkeypatch.setenv("NOVELTY_NUM_THREADS", "1")
    serial = det.novelty(probe)
    monkeypatch.setattr(scoring, "CHUNK", 1000)
    monkeypatch.setenv("NOVELTY_NUM_THREADS", "3")
    assert scoring.threads() == 3
    threaded = det.novelty(probe)
    np.testing.assert_array_equal(threaded, serial)
    expected_rows, _ = reference(det.clusterer_.weights_, probe)
    np.testing.assert_array_equal(threaded, det.synapse_.efficacy_[expected_rows])


@pytest.mark.parametrize("value", ["2", "0", "-1", "x", ""])
def test_the_number_of_threads(monkeypatch, value):
    monkeypatch.setenv("NOVELTY_NUM_THREADS", value)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    assert scoring.threads() == (2 if value == "2" else cores)


def test_read_only_and_strided_batches():
    det = novelty.make("hsom").fit(corridor(500))
    X = np.asfortranarray(np.random.default_rng(1).uniform(0, 1, (3000, 16)))
    expected_rows, _ = reference(det.clusterer_.weights_, X)
    expected = det.synapse_.efficacy_[expected_rows]
    np.testing.assert_array_equal(det.novelty(X), expected)
    X.flags.writeable = False
    np.testing.assert_array_equal(det.novelty(X), expected)
    C = np.ascontiguousarray(X)
    C.flags.writeable = False
    np.testing.assert_array_equal(det.novelty(C), expected)
    every_other = np.repeat(X, 2, axis=0)[::2]  # a strided view
    np.testing.assert_array_equal(det.novelty(every_other), expected)
