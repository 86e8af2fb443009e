"""The detector API's conventions: dict scans read by key, DataFrame column
names, the first perception before any learning; and what the base class
guarantees every detector (bounded scans, transactional fits, finite novelty,
thread safety)."""

import contextlib
import threading
import warnings

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

import novelty
from novelty._component import StateError
from novelty._validation import MAX_SCAN_NORM
from novelty.registry import detectors
from novelty.testing.conformance import _assert_same_state, _state_arrays
from tests.damaged import damaging

from .registered import detector_params

NAMES = ["front", "left", "right", "rear"]  # sorted: front, left, rear, right
SORTED = sorted(NAMES)


def scans(n=40, seed=0):
    return np.random.default_rng(seed).uniform(size=(n, len(NAMES)))


def as_dicts(X, order=NAMES):
    """Column j of X is feature NAMES[j]; the keys are inserted in ``order``."""
    return [{n: float(x[NAMES.index(n)]) for n in order} for x in X]


def small_hsom(**params):
    return novelty.make("hsom", n_rows=3, n_columns=3, **params)


class Table:
    """The least a DataFrame offers that the detectors use: ``columns`` and ``__array__``."""

    def __init__(self, values, columns):
        self.values, self.columns = np.asarray(values, dtype=np.float64), list(columns)
        self.shape = self.values.shape

    def __array__(self, dtype=None, copy=None):
        return self.values if dtype is None else self.values.astype(dtype)

    def __len__(self):
        return self.shape[0]


def online_detectors():
    out = []
    for name in detectors.names():
        det = novelty.make(name)
        if det.supports_online and getattr(det, "input_layout", None) is None:  # dict scans of any names
            out.append(pytest.param(det, id=name))
    return out


# ------------------------------------------------------------- dict scans
def test_river_loop_with_dict_scans_equals_the_stream_in_sorted_key_order():
    X = scans()
    det = small_hsom()
    got = []
    for x in as_dicts(X):
        s = det.score_one(x)
        det.learn_one(x)
        got.append(s)
    ref = small_hsom()
    order = [NAMES.index(n) for n in SORTED]
    expected = [ref.score_one(X[0, order])] + list(ref.stream(X[:, order]))
    # score_one before learning is y0; then each scan scored before it is learned
    assert got[0] == 1.0
    np.testing.assert_array_equal(got[1:], expected[2:])
    np.testing.assert_array_equal(det.feature_names_in_, SORTED)
    assert det.feature_names_in_.dtype == object


@pytest.mark.parametrize("det", online_detectors())
def test_river_loop_works_from_the_first_scan_for_every_online_detector(det):
    X = scans(12)
    first = clone(det).score_learn_one(as_dicts(X)[0])
    out = []
    for x in as_dicts(X):
        s = det.score_one(x)
        det.learn_one(x)
        out.append(s)
    assert out[0] == first  # the novelty of a first perception, learned or not
    assert all(0.0 <= s <= 1.0 for s in out)
    np.testing.assert_array_equal(det.feature_names_in_, SORTED)


@pytest.mark.parametrize("name", ["hsom", "gwr-novelty", "som-wang-hsu", "kohonen-filter",
                                  "isolation-forest", "gmm"])
def test_any_key_order_gives_identical_results(name):
    X = scans(30)
    runs = []
    for order in (NAMES, NAMES[::-1], [NAMES[2], NAMES[0], NAMES[3], NAMES[1]]):
        det = novelty.make(name)
        if det.supports_online:
            out = [det.score_learn_one(x) for x in as_dicts(X, order)]
        else:
            det.fit(Table(X[:, [NAMES.index(n) for n in SORTED]], SORTED))
            out = []
        # scoring reads dicts by key in whatever order they come
        out += [det.score_one(dict(reversed(list(x.items())))) for x in as_dicts(X[::-1], order)]
        runs.append(out)
    assert runs[0] == runs[1] == runs[2]


def test_the_same_features_reversed_are_not_a_new_perception():
    # The reversed dict used to be read by insertion order: a different, fully novel scan.
    det = small_hsom()
    x = dict(zip(NAMES, [0.1, 0.9, 0.3, 0.7]))
    det.learn_one(x)
    reversed_x = dict(reversed(list(x.items())))
    assert det.score_one(reversed_x) == det.score_one(x) == pytest.approx(0.6997, abs=1e-4)


def test_integer_keys_are_sorted_numerically():
    det = small_hsom()
    det.learn_one({2: 0.3, 0: 0.1, 1: 0.2, 10: 0.4})
    np.testing.assert_array_equal(det.feature_names_in_, [0, 1, 2, 10])
    assert det.feature_names_in_.dtype == np.int64
    twin = small_hsom()
    twin.learn_one(np.array([0.1, 0.2, 0.3, 0.4]))
    np.testing.assert_array_equal(det.clusterer_.weights_, twin.clusterer_.weights_)


@pytest.mark.parametrize("x, message", [
    ({"front": 0.1, "left": 0.2, "rear": 0.3}, r"yet now missing:\n- right\n"),
    ({**dict(zip(NAMES, [0.1] * 4)), "top": 0.5}, r"unseen at fit time:\n- top\n"),
    ({"front": 0.1, "left": 0.2, "rear": 0.3, "up": 0.4},
     r"unseen at fit time:\n- up\nFeature names seen at fit time, yet now missing:\n- right\n"),
    ({0: 0.1, 1: 0.2, 2: 0.3, 3: 0.4}, r"unseen at fit time:\n- 0\n- 1\n- 2\n- 3\n"),
])
@pytest.mark.parametrize("method", ["score_one", "learn_one", "score_learn_one"])
def test_a_missing_or_extra_key_is_refused_by_name_and_changes_nothing(x, message, method):
    det = small_hsom()
    for d in as_dicts(scans(5)):
        det.learn_one(d)
    weights, efficacy = det.clusterer_.weights_.copy(), det.synapse_.efficacy_.copy()
    with pytest.raises(ValueError, match=r"keys of x do not match the features HabituatingFilter learned"):
        getattr(det, method)(x)
    with pytest.raises(ValueError, match=message):
        getattr(det, method)(x)
    np.testing.assert_array_equal(det.clusterer_.weights_, weights)
    np.testing.assert_array_equal(det.synapse_.efficacy_, efficacy)


def test_keys_of_mixed_types_are_refused():
    det = small_hsom()
    with pytest.raises(ValueError, match=r"all strings or all integers.*int, str"):
        det.learn_one({"a": 0.1, 1: 0.2})
    assert not hasattr(det, "n_features_in_")
    with pytest.raises(ValueError, match=r"all strings or all integers.*bool"):
        det.score_one({True: 0.1, False: 0.2})


def test_a_dict_scan_for_a_model_learned_from_arrays_is_refused():
    det = small_hsom().fit(scans())
    with pytest.raises(ValueError, match=r"learned from arrays without feature names.*4 features"):
        det.score_one(dict(zip(NAMES, [0.5] * 4)))


def test_an_array_scan_for_a_model_learned_from_dicts_is_read_in_the_names_order():
    det = small_hsom()
    for d in as_dicts(scans()):
        det.learn_one(d)
    x = dict(zip(NAMES, [0.1, 0.9, 0.3, 0.7]))
    assert det.score_one(np.array([x[n] for n in det.feature_names_in_])) == det.score_one(x)


# -------------------------------------------------------- the first perception
def test_score_one_before_learning_is_y0_and_learns_nothing():
    det = small_hsom()
    assert det.score_one(np.full(4, 0.5)) == 1.0
    assert novelty.make("hsom", y0=0.8, alpha=1.5).score_one([0.5, 0.5]) == 0.8
    assert novelty.make("gwr-wang-hsu").score_one({"a": 1.0}) == 1.0
    assert not hasattr(det, "n_features_in_") and not hasattr(det, "clusterer_")
    with pytest.raises(NotFittedError):
        det.novelty(np.zeros((1, 4)))


def test_score_one_before_learning_checks_the_scan_and_the_parameters():
    with pytest.raises(ValueError, match="NaN or infinity"):
        small_hsom().score_one([0.5, np.nan])
    with pytest.raises(ValueError, match=r"The 'stimulus' parameter of HabituatingFilter"):
        small_hsom(stimulus=-1.0).score_one([0.5, 0.5])
    with pytest.raises(ValueError, match=r"'y0' parameter"):
        novelty.make("hsom", y0="high").score_one([0.5, 0.5])


@pytest.mark.parametrize("name", ["isolation-forest", "gmm", "parzen", "kohonen-filter", "som-distance"])
def test_a_baseline_scores_a_first_perception_at_the_top_of_its_scale(name):
    det = novelty.make(name)
    assert det.score_one(np.full(3, 0.5)) == 1.0
    with pytest.raises(NotFittedError):
        det.score_samples(np.zeros((1, 3)))


# ------------------------------------------------------------- DataFrames
def test_a_table_fixes_the_feature_names_and_later_tables_must_match():
    X = scans()
    det = small_hsom().fit(Table(X, NAMES))
    np.testing.assert_array_equal(det.feature_names_in_, NAMES)  # column order, as scikit-learn
    np.testing.assert_array_equal(det.novelty(Table(X, NAMES)), small_hsom().fit(X).novelty(X))
    with pytest.raises(ValueError, match=r"must be in the same order as they were in fit"):
        det.novelty(Table(X, NAMES[::-1]))
    with pytest.raises(ValueError, match=r"unseen at fit time:\n- a\n- b\n- c\n- d\n"):
        det.predict(Table(X, list("abcd")))
    with pytest.raises(ValueError, match=r"should match those that were passed during fit"):
        det.partial_fit(Table(X, NAMES[::-1]))
    with pytest.warns(UserWarning, match="X does not have valid feature names, but HabituatingFilter"):
        det.score_samples(X)
    # a dict scan is read by key against the table's names
    x = X[0]
    assert det.score_one(dict(zip(NAMES[::-1], x[::-1].tolist()))) == det.score_one(x)


def test_a_refit_without_names_forgets_them():
    det = small_hsom().fit(Table(scans(), NAMES))
    det.fit(scans())
    assert not hasattr(det, "feature_names_in_")
    with pytest.warns(UserWarning, match="X has feature names, but HabituatingFilter was fitted without"):
        det.novelty(Table(scans(), NAMES))


def test_pandas_dataframes_when_pandas_is_installed():
    pd = pytest.importorskip("pandas", reason="pandas is not installed (it is not a dependency)")
    X = scans()
    det = small_hsom().fit(pd.DataFrame(X, columns=NAMES))
    np.testing.assert_array_equal(det.feature_names_in_, NAMES)
    np.testing.assert_array_equal(det.novelty(pd.DataFrame(X, columns=NAMES)), small_hsom().fit(X).novelty(X))
    with pytest.raises(ValueError, match="same order"):
        det.novelty(pd.DataFrame(X[:, ::-1], columns=NAMES[::-1]))


# ------------------------------------------------- thresholds: PyOD's attributes
def test_decision_scores_are_the_fitted_models_novelty_of_the_training_scans():
    X = scans(60)
    det = small_hsom().fit(X)
    np.testing.assert_array_equal(det.decision_scores_, det.novelty(X))
    assert det.threshold_ == 0.5  # contamination="auto": the fixed threshold
    np.testing.assert_array_equal(det.labels_, (det.predict(X) == -1).astype(int))
    assert det.labels_.dtype.kind == "i"


def test_contamination_threshold_is_the_quantile_of_the_training_scores():
    det = small_hsom(contamination=0.2).fit(scans(10))
    det.decision_scores_ = np.arange(1, 11) / 10  # 0.1 ... 1.0, by hand
    # (1 - 0.2) quantile, linear: position 0.8 * 9 = 7.2, so 0.8 + 0.2 * 0.1
    assert det.threshold_ == pytest.approx(0.82, abs=1e-15)
    np.testing.assert_array_equal(det.labels_, [0] * 8 + [1, 1])
    assert det.offset_ == -det.threshold_
    det.set_params(contamination=0.5)  # takes effect at once
    assert det.threshold_ == pytest.approx(0.55, abs=1e-15)
    np.testing.assert_array_equal(det.labels_, [0] * 5 + [1] * 5)


def test_contamination_wins_over_threshold_and_predict_uses_it():
    X = scans(200)
    det = novelty.make("hsom", threshold=0.99, contamination=0.1).fit(X)
    assert det.threshold_ == np.quantile(det.decision_scores_, 0.9)
    nov = det.novelty(X)
    np.testing.assert_array_equal(det.predict(X), np.where(nov > det.threshold_, -1, 1))
    np.testing.assert_allclose(det.decision_function(X), det.threshold_ - nov)
    assert 0 < det.labels_.sum() <= 20


def test_hsom_default_threshold_and_predictions_are_unchanged():
    X = scans(200)
    det = novelty.make("hsom").fit(X)
    assert det.contamination == "auto" and det.threshold_ == 0.5
    np.testing.assert_array_equal(det.predict(X), np.where(det.novelty(X) > 0.5, -1, 1))


@pytest.mark.parametrize("value", [0, 0.0, 0.5000001, -0.1, 1.0, "high", True, np.nan, None])
def test_a_bad_contamination_is_refused_before_fitting(value):
    det = small_hsom(contamination=value)
    with pytest.raises(ValueError, match=r"The 'contamination' parameter of HabituatingFilter must be "
                                         r"one of 'auto' or a float in \(0, 0.5\]"):
        det.fit(scans())
    assert not hasattr(det, "n_features_in_")


def test_contamination_needs_the_training_scans_of_fit():
    det = small_hsom(contamination=0.1)
    det.stream(scans())
    with pytest.raises(ValueError, match=r"contamination=0.1 sets the threshold from .*only 'fit' records"):
        det.predict(scans(3))
    with pytest.raises(AttributeError, match="learned online only"):
        _ = det.labels_
    det.set_params(contamination="auto")
    assert det.threshold_ == 0.5 and det.predict(scans(3)).shape == (3,)


def test_unfitted_threshold_attributes_raise_not_fitted():
    det = small_hsom()
    for name in ("threshold_", "labels_", "offset_"):
        with pytest.raises(NotFittedError):
            getattr(det, name)
        assert not hasattr(det, name)


@pytest.mark.parametrize("name", ["kohonen-filter", "autoencoder-filter", "gmm", "lof", "knn", "parzen"])
def test_baselines_fitted_with_contamination_flag_that_fraction(name):
    X = np.random.default_rng(3).normal(size=(100, 3))
    det = novelty.make(name, contamination=0.1).fit(X)
    np.testing.assert_array_equal(det.decision_scores_, det.novelty(X))
    assert det.labels_.sum() == 10  # continuous scores: no ties at the quantile
    np.testing.assert_array_equal(det.predict(X) == -1, det.labels_ == 1)


# ------------------------------------------------------------------------------
# What the base class guarantees every registered detector: scans beyond the
# norm bound refused with the state unchanged and scans within it keeping the
# state finite; a failed fit keeping the previous model; no non-finite novelty
# returned; learning from several threads leaving a consistent model.

N_FEATURES = 4
DETECTORS = detector_params(any_rows=True)
QUICK = {"autoencoder-filter": {"max_iter": 20}, "isolation-forest": {"n_estimators": 10}}


def make_quick(name: str):
    return novelty.make(name, **QUICK.get(name, {}))


def data(n: int = 40, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(size=(n, N_FEATURES))


def fitted_quick(name: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return make_quick(name).fit(data())


def learn(det, X):
    """Learn ``X`` the way the detector can: online, or a batch refit."""
    if det.supports_online:
        return det.partial_fit(X)
    return det.fit(X)


def finite_state(det) -> list[str]:
    return [k for k, v in _state_arrays(det).items() if v.dtype.kind == "f" and not np.all(np.isfinite(v))]


# ------------------------------------------------------------- input bound
@pytest.mark.parametrize("name", DETECTORS)
def test_a_scan_beyond_the_norm_bound_is_refused_and_changes_nothing(name):
    det = fitted_quick(name)
    before = _state_arrays(det)
    X = data(3, seed=1)
    X[1, 2] = 1e155  # its squared distances overflow
    with pytest.raises(ValueError, match=r"norm above 1e\+100"):
        learn(det, X)
    if det.supports_online:
        with pytest.raises(ValueError, match=r"norm above 1e\+100"):
            det.learn_one(X[1])
    _assert_same_state(before, _state_arrays(det), name)


@pytest.mark.parametrize("name", DETECTORS)
def test_an_integer_beyond_float64_is_a_value_error_and_changes_nothing(name):
    det = fitted_quick(name)
    before = _state_arrays(det)
    n = det.n_features_in_
    with pytest.raises(ValueError, match=r"integer beyond the float64 range"):
        learn(det, [[10**400] * n] * 2)
    if det.supports_online:
        with pytest.raises(ValueError, match=r"integer beyond the float64 range"):
            det.learn_one([10**400] * n)
    _assert_same_state(before, _state_arrays(det), name)


@pytest.mark.parametrize("name", DETECTORS)
def test_scans_at_the_bound_keep_the_state_finite_and_saveable(name, tmp_path):
    det = fitted_quick(name)
    big = data(3, seed=2)
    big *= 0.999 * MAX_SCAN_NORM / np.linalg.norm(big, axis=1, keepdims=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            learn(det, np.vstack([big, data(3, seed=3)]))
        except ValueError as exc:  # a batch model may refuse such data, by name
            assert "fail" in str(exc) or "component" in str(exc), exc
    assert finite_state(det) == []
    assert np.all(np.isfinite(det.novelty(np.vstack([big, data(2)]))))
    if name == "habituating" or getattr(det, "random_state", 0) is None:
        return
    det.save(tmp_path / "model.npz")
    novelty.load(tmp_path / "model.npz")


# -------------------------------------------------------- transactional fit
@pytest.mark.parametrize("name", DETECTORS)
def test_a_fit_that_fails_keeps_the_previous_model(name, monkeypatch):
    det = fitted_quick(name)
    before, scores = _state_arrays(det), det.novelty(data(5, seed=4))

    def broken(self, X, dt):
        raise RuntimeError("learning failed")

    monkeypatch.setattr(type(det), "_learn", broken)
    with pytest.raises(RuntimeError, match="learning failed"):
        det.fit(data(30, seed=5))
    monkeypatch.undo()
    _assert_same_state(before, _state_arrays(det), name)
    np.testing.assert_array_equal(det.novelty(data(5, seed=4)), scores)


@pytest.mark.parametrize(
    "name, message",
    [
        ("gmm", r"minimum of 2 is required"),
        ("elliptic-envelope", r"minimum of 2 is required"),
        ("lof", r"needs at least 2 samples .*n_samples = 1"),
        ("knn", r"more training inputs than n_neighbors=5 .*n_samples = 1"),
    ],
)
def test_a_refit_on_too_few_samples_names_the_need_and_keeps_the_model(name, message):
    det = fitted_quick(name)
    before, scores = _state_arrays(det), det.novelty(data(5, seed=4))
    with pytest.raises(ValueError, match=message):
        det.fit(data(1, seed=6))
    _assert_same_state(before, _state_arrays(det), name)
    np.testing.assert_array_equal(det.novelty(data(5, seed=4)), scores)
    assert not np.all(scores == 1.0)


def test_a_failed_first_stream_leaves_the_detector_unfitted(monkeypatch):
    det = novelty.make("hsom")
    monkeypatch.setattr(type(det), "_learn", lambda self, X, dt: 1 / 0)
    with pytest.raises(ZeroDivisionError):
        det.partial_fit(data(3))
    with pytest.raises(ZeroDivisionError):
        det.learn_one(data(1)[0])
    assert not hasattr(det, "n_features_in_") and not hasattr(det, "clusterer_")


# ------------------------------------------------------- no NaN novelty out
def damaged(name: str):
    """A fitted detector whose every learned float array holds NaN."""
    det = fitted_quick(name)

    def poison(obj):
        arrays, _, children = obj._export_state()
        for key, value in arrays.items():
            if value.dtype.kind == "f" and value.size:
                getattr(obj, key)[...] = np.nan
        for child in children.values():
            poison(child)

    with damaging(det) if hasattr(det, "synapse_") else contextlib.nullcontext():
        poison(det)
    det._rebuild_scratch() if hasattr(det, "reference_") else None
    return det


@pytest.mark.parametrize("name", ["hsom", "gwr-novelty", "kohonen-filter", "som-distance", "parzen"])
def test_a_damaged_state_raises_instead_of_returning_nan(name):
    det = damaged(name)
    X = data(3)
    for method in ("novelty", "score_samples", "decision_function", "predict"):
        with pytest.raises(StateError, match="not finite"):
            getattr(det, method)(X)
    with pytest.raises(StateError, match="not finite"):
        det.score_one(X[0])


# ------------------------------------------------------------------ threads
@pytest.mark.parametrize("call", ["learn_one", "score_learn_one", "score_one"])
def test_single_scan_calls_wait_for_the_detectors_own_lock(call):
    """A fitted detector's engine comes from the clone its fit learned on; the single-scan calls
    must still wait for this detector's lock (they once took the clone's, and raced stream)."""
    from novelty._kernels import wait
    from novelty.detector import lock_of

    det = make_quick("gng-stanley").fit(data(30))
    wait(det.clusterer_, det.synapse_)
    det.learn_one(data(1, seed=1)[0])  # the engine is built and serves single scans
    done = threading.Event()
    worker = threading.Thread(target=lambda: (getattr(det, call)(data(1, seed=2)[0]), done.set()))
    with lock_of(det):
        worker.start()
        assert not done.wait(0.3), f"{call} ran while another thread held the detector's lock"
    worker.join(30)
    assert done.is_set()


def test_each_detector_has_its_own_lock_through_copies_pickles_and_fits():
    """A deep copy or a pickle gets a fresh, unheld lock (never the original's, even while that
    one is held); a refit keeps the detector's own lock (not its clone's); a shallow copy,
    which shares the learned arrays, shares the lock that guards them."""
    import copy
    import pickle

    from novelty.detector import lock_of

    det = make_quick("hsom").fit(data(10))
    lock = lock_of(det)
    assert lock_of(det) is lock
    with lock:
        twins = [copy.deepcopy(det), pickle.loads(pickle.dumps(det))]
        for twin in twins:
            other = lock_of(twin)
            assert other is not lock
            acquired = []

            def take(other=other, acquired=acquired):
                acquired.append(other.acquire(timeout=5))
                if acquired[-1]:
                    other.release()

            worker = threading.Thread(target=take)
            worker.start()
            worker.join(10)
            assert acquired == [True]  # unheld, although the original is held here
    det.fit(data(12, seed=3))
    assert lock_of(det) is lock
    assert lock_of(copy.copy(det)) is lock
    assert "_lock" not in det.get_params()


@pytest.mark.parametrize("name", ["gng-stanley", "gwr-novelty", "hsom", "gng-wang-hsu"])
def test_learning_from_several_threads_leaves_a_consistent_model(name, tmp_path):
    det = make_quick(name)
    det.fit(data(5))
    streams = [np.random.default_rng(s).uniform(size=(150, N_FEATURES)) for s in range(4)]
    errors: list[BaseException] = []
    learned = [5]  # the fit's scans; list.append is atomic
    start = threading.Barrier(len(streams) + 1)

    def worker(X):
        start.wait()
        try:
            for i, x in enumerate(X):
                if i % 3:
                    det.learn_one(x)
                else:
                    det.partial_fit(X[i:i + 2])
                learned.append(1 if i % 3 else len(X[i:i + 2]))
                det.score_one(x)
        except BaseException as exc:  # reported below, in the main thread
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(X,)) for X in streams]
    for t in threads:
        t.start()
    start.wait()
    scores = [det.novelty(data(20)) for _ in range(20)]  # scoring while the others learn
    for t in threads:
        t.join()
    assert errors == []
    assert all(np.all(np.isfinite(s)) for s in scores)
    counter = "n_inputs_" if hasattr(det.clusterer_, "n_inputs_") else "n_updates_"
    if hasattr(det.clusterer_, counter):  # every scan was learned exactly once
        assert getattr(det.clusterer_, counter) == sum(learned)
    det.save(tmp_path / "model.npz")
    loaded = novelty.load(tmp_path / "model.npz")
    np.testing.assert_array_equal(loaded.novelty(data(5)), det.novelty(data(5)))
