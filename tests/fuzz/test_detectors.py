"""Fuzzing every registered detector's public methods with invalid and extreme input.

For each registered detector and each public method (``fit``, ``partial_fit``,
``stream``, ``learn_one``, ``score_one``, ``score_learn_one``, ``novelty``,
``score_samples``, ``decision_function``, ``predict``) hypothesis draws an
input -- arrays of any shape with NaN, infinities, huge and tiny finite values,
arrays of other dtypes (complex, dates, strings, booleans, integers), strings,
dicts, None, ragged lists -- and, for the learning methods, timestamps (going
backwards, huge, NaN, complex). Each call must either

- give a result that is finite, with a learned state that is finite and that
  saves to a file which loads and scores the same; or
- raise ``ValueError`` or ``TypeError`` (the library's own errors derive from
  them) with a message, the learned state byte-identical to before.

The examples are bounded so that the module takes well under a minute on two
cores; under CI (``CI`` set) the example sequence is fixed (``conftest.py``).
Run with ``-s`` to see how many calls of each kind were tried.
"""

from __future__ import annotations

import collections
import tempfile
import warnings
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from sklearn.base import clone

import novelty
from novelty.testing.conformance import _state_arrays

from ..registered import detector_params

N_FEATURES = 3
#: small versions of the detectors, so that each call is quick
QUICK = {
    "autoencoder-filter": {"max_iter": 15},
    "gmm": {"max_components": 2, "max_iter": 20},
    "isolation-forest": {"n_estimators": 8},
    "hsom": {"clusterer__n_rows": 4, "clusterer__n_columns": 4},
    "som-wang-hsu": {"clusterer__n_rows": 4, "clusterer__n_columns": 4},
}
METHODS = ["fit", "partial_fit", "stream", "learn_one", "score_one", "score_learn_one", "novelty",
           "score_samples", "decision_function", "predict"]
LEARNING = {"fit", "partial_fit", "stream", "learn_one", "score_learn_one"}
EXAMPLES_PER_DETECTOR = 80

#: what the module tried: (method, outcome) -> count
TRIED: collections.Counter = collections.Counter()

EXTREMES = [0.0, -0.0, 5e-324, 1e-300, 5e99, -5e99, 1e101, 1e155, -1e200, 1.7e308, -1.7e308,
            np.nan, np.inf, -np.inf]
values = st.one_of(st.floats(-2.0, 2.0), st.sampled_from(EXTREMES))
shapes = st.one_of(
    st.tuples(st.integers(0, 4), st.sampled_from([N_FEATURES, N_FEATURES, N_FEATURES - 1, N_FEATURES + 1, 0])),
    st.tuples(st.sampled_from([N_FEATURES, N_FEATURES - 1, 0])),
    st.sampled_from([(), (1, 1, N_FEATURES)]),
)
float_arrays = hnp.arrays(np.float64, shapes, elements=values)
other_arrays = hnp.arrays(
    st.sampled_from([np.float32, np.int64, np.uint8, np.bool_, np.complex128, "datetime64[s]",
                     "timedelta64[ms]", "U3", "S2"]),
    shapes,
)
others = st.one_of(
    st.text(max_size=4),
    st.none(),
    st.dictionaries(st.text(max_size=2), values, max_size=N_FEATURES + 1),
    st.dictionaries(st.integers(0, N_FEATURES), st.floats(-1, 1), max_size=N_FEATURES + 1),
    st.lists(st.lists(values, max_size=N_FEATURES + 1), max_size=3),  # possibly ragged
    st.lists(st.one_of(values, st.text(max_size=2), st.none(), st.complex_numbers(max_magnitude=2)),
             min_size=N_FEATURES, max_size=N_FEATURES),
    values,
)
inputs = st.one_of(float_arrays, other_arrays, others)


def well_formed(one_scan: bool):
    """A scan or a batch of the right shape, its values ordinary or, now and then, extreme."""
    shape = st.just((N_FEATURES,)) if one_scan else st.tuples(st.integers(1, 5), st.just(N_FEATURES))
    ordinary = st.floats(-2.0, 2.0)
    return hnp.arrays(np.float64, shape, elements=st.one_of(*[ordinary] * 15, st.sampled_from(EXTREMES)))
timestamps = st.one_of(
    *[st.none()] * 6,
    st.floats(-10.0, 1e12),
    st.sampled_from([1e300, -1e300, np.nan, np.inf, 1.0 + 2.0j, "x", np.datetime64(5, "s")]),
    st.lists(st.one_of(st.floats(-10.0, 1e300), st.sampled_from([np.nan, -1e300])), max_size=5),
)


def quick(name: str):
    return novelty.make(name, **QUICK.get(name, {}))


def familiar(n: int = 30, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(size=(n, N_FEATURES))


def snapshot(det) -> dict:
    state = {k: v.tobytes() + str(v.dtype).encode() + str(v.shape).encode()
             for k, v in _state_arrays(det).items()}
    state["params"] = repr(det.get_params(deep=False))
    state["attributes"] = sorted(k for k in vars(det) if not k.startswith("_"))
    return state


def call(det, method: str, x, t):
    one = method in ("learn_one", "score_one", "score_learn_one")
    if method == "score_one":
        return det.score_one(x)
    if one:
        return getattr(det, method)(x, t)
    if method in ("fit", "partial_fit", "stream"):
        if method == "partial_fit" and not det.supports_online:
            return det.fit(x, timestamps=t)
        return getattr(det, method)(x, timestamps=t)
    return getattr(det, method)(x)


def assert_finite_result(det, out) -> None:
    if out is det:
        return
    out = np.asarray(out, dtype=np.float64)
    assert np.all(np.isfinite(out)), out


def assert_saves_and_loads(det) -> None:
    probe = np.random.default_rng(1).uniform(size=(4, det.n_features_in_))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model.npz"
        det.save(path)
        back = novelty.load(path)
    np.testing.assert_array_equal(back.novelty(probe), det.novelty(probe))


@pytest.fixture(scope="module", autouse=True)
def _report_counts():
    yield
    outcomes = collections.Counter()
    for (_, outcome), n in TRIED.items():
        outcomes[outcome] += n
    print(f"\nfuzz: {sum(TRIED.values())} calls; by outcome {dict(outcomes)}")
    for method in METHODS + ["save/load"]:
        print(f"  {method}: " + ", ".join(f"{o} {n}" for (m, o), n in sorted(TRIED.items()) if m == method))


@pytest.mark.parametrize("name", detector_params(any_rows=True))
def test_invalid_and_extreme_input_gives_a_finite_result_or_a_clear_error(name):
    fitted = quick(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fitted.fit(familiar())

    # a sequence of its own for each detector (under CI's fixed sequences too)
    @seed(zlib.crc32(name.encode()))
    @settings(max_examples=EXAMPLES_PER_DETECTOR, suppress_health_check=[HealthCheck.too_slow])
    @given(method=st.sampled_from(METHODS), good=st.integers(0, 2), data=st.data(), t=timestamps,
           fresh=st.booleans(), check_file=st.integers(0, 3))
    def fuzz(method, good, data, t, fresh, check_file):
        # two in three calls get well-formed data (which may still hold an extreme value)
        x = data.draw(well_formed(method.endswith("_one")) if good else inputs, label="x")
        det = clone(fitted) if fresh and method in LEARNING else fitted
        before = snapshot(det)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                out = call(det, method, x, t)
            except (ValueError, TypeError) as exc:
                TRIED[method, "refused"] += 1
                assert str(exc).strip(), f"{type(exc).__name__} without a message"
                assert snapshot(det) == before, f"{method} was refused but changed the state"
                return
        TRIED[method, "finite"] += 1
        assert_finite_result(det, out)
        state = _state_arrays(det)
        assert all(np.all(np.isfinite(v)) for v in state.values() if v.dtype.kind == "f"), method
        if method in LEARNING and check_file == 0:
            TRIED["save/load", "round trip"] += 1
            assert_saves_and_loads(det)
        if fitted.n_features_in_ != N_FEATURES:  # a fit on other data: back to the usual shape
            fitted.fit(familiar())

    fuzz()
