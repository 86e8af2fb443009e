"""What the kernel tests share: the reference with its winners, the kernel with its, streams."""

from __future__ import annotations

import copy

import numpy as np
from hypothesis import strategies as st

from novelty import _kernels
from novelty.filter import HabituatingFilter, learn_stream

reference_only = _kernels.reference_loops


def reference_learn(clusterer, synapse, X, dt, stimulus, distances=None):
    """``learn_stream``, also returning the winner of each row."""
    winners = []
    match = clusterer.match

    def recording(x):
        m = match(x)
        winners.append(m.winner)
        return m

    clusterer.match = recording
    try:
        out = learn_stream(clusterer, synapse, X, dt, stimulus, distances=distances)
    finally:
        del clusterer.match
    return out, np.array(winners, dtype=np.int64)


def kernel_learn(clusterer, synapse, X, dt, stimulus, distances=None):
    """The pair's compiled driver (waited for), also returning the winner of each row."""
    assert _kernels.wait(clusterer, synapse) is not None
    engine = _kernels.choose(clusterer, synapse)
    assert engine.driving  # the driver, not the reference
    winners = np.empty(X.shape[0], dtype=np.int64)
    out = engine.learn(X, dt, stimulus, distances=distances, winners=winners)
    return out, winners


def assert_same_state(a, b):
    """Every piece of learned state of two components (nested ones too) is equal, bit for bit."""
    assert type(a) is type(b)
    names = sorted(n for n in vars(b) if n.endswith("_") and not n.startswith("_"))
    assert names == sorted(n for n in vars(a) if n.endswith("_") and not n.startswith("_"))
    for name in names + [n for n in ("_table_radius",) if hasattr(b, n)]:
        got, expected = getattr(a, name), getattr(b, name)
        if isinstance(expected, np.ndarray):
            assert got.dtype == expected.dtype, name
            np.testing.assert_array_equal(got, expected, err_msg=name)
        elif hasattr(expected, "get_params"):
            assert_same_state(got, expected)
        else:
            assert got == expected, name


def assert_same_filter(a: HabituatingFilter, b: HabituatingFilter):
    assert_same_state(a.clusterer_, b.clusterer_)
    assert_same_state(a.synapse_, b.synapse_)
    assert a.match_scale_ == b.match_scale_


def both(clusterer, synapse):
    """Two identical copies of a fitted pair."""
    return (clusterer, synapse), (copy.deepcopy(clusterer), copy.deepcopy(synapse))


def within_fixed_point(fraction: float, alpha: float, y0: float) -> float:
    """A stimulus ``fraction`` of the way up to Stanley's fixed point at 0 (``S = alpha y0``),
    never past it by a rounding (``y0 - S / alpha >= 0``, as the filter checks it)."""
    stimulus = fraction * alpha * y0
    while y0 - stimulus / alpha < 0:
        stimulus = float(np.nextafter(stimulus, 0.0))
    return stimulus


def corridor(n_scans, n_features=16, seed=0):
    """A smooth random walk in [0, 1]^n_features, like sonar scans along corridors."""
    rng = np.random.default_rng(seed)
    X = np.empty((n_scans, n_features))
    x = rng.uniform(0.2, 0.8, n_features)
    for i in range(n_scans):
        x = np.clip(x + rng.normal(0, 0.03, n_features), 0.0, 1.0)
        X[i] = x
    return X


finite = dict(allow_nan=False, allow_infinity=False)


@st.composite
def streams(draw, max_features=40):
    n_features = draw(st.integers(1, max_features))
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
    {"novelty_rule": "mismatch", "match_scale": "scott", "calibration_scans": 7},
])
