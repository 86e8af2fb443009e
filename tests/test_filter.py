"""The habituating novelty filter: the paper's constants, the Euler descent of a
repeated scan, learning on and off, streaming == batch, scikit-learn conventions,
the novelty rules and determinism (routing, the parts after fitting, calibrating and the
range warning: tests/_filter)."""

import copy

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from sklearn.base import clone

import novelty
from novelty._component import StateError
from novelty.clusterers.som import SOM
from novelty.filter import HabituatingFilter
from novelty.habituation.stanley import StanleySynapse
from tests.damaged import damaging

TAU, ALPHA = 3.33, 1.05
REST = 1 - 1 / ALPHA


def euler(n):
    """Efficacy of a synapse that has won n times in a row (closed form of the Euler step)."""
    return REST + (1 - REST) * (1 - ALPHA / TAU) ** n


def data(n=60, d=4, seed=0):
    return np.random.default_rng(seed).uniform(size=(n, d))


def small(**params):
    return novelty.make("hsom", n_rows=4, n_columns=5, **params)


def state(det):
    """Every learned array and value of a fitted filter, copied."""
    out = {"n_features_in_": det.n_features_in_, "last_time_": det.last_time_}
    for part in ("clusterer_", "synapse_"):
        for name, value in vars(getattr(det, part)).items():
            if name not in ("_changes", "_held", "_writing", "_locked"):  # not state: the count of
                # attributes set, the marks of the engine that holds, writes and locks the part
                out[f"{part}.{name}"] = value.copy() if isinstance(value, np.ndarray) else value
    return out


def assert_same_state(a, b):
    assert a.keys() == b.keys()
    for key in a:
        if isinstance(a[key], np.ndarray):
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
            assert a[key].dtype == b[key].dtype, key
        elif isinstance(a[key], list):  # SOM neighbour table
            assert len(a[key]) == len(b[key])
            for u, v in zip(a[key], b[key]):
                np.testing.assert_array_equal(u, v, err_msg=key)
        else:
            assert a[key] == b[key], key


# -------------------------------------------------------- the paper's values
def test_hsom_without_arguments_carries_every_constant_of_the_paper():
    det = novelty.make("hsom")
    assert isinstance(det, HabituatingFilter)
    som, syn = det.clusterer, det.synapse
    assert isinstance(som, SOM) and isinstance(syn, StanleySynapse)
    assert (som.n_rows, som.n_columns) == (10, 10)
    assert som.learning_rate == 0.25
    assert som.radius == 1
    assert som.decay == "constant"
    assert syn.tau_winner == 3.33 and syn.tau_neighbour == 14.3
    assert syn.alpha == 1.05 and syn.y0 == 1.0
    assert syn.method == "euler"
    assert syn.others == "hold" and syn.tau_forget is None
    assert det.stimulus == 1.0 and det.n_epochs == 1
    assert round(det.resting_novelty, 4) == 0.0476
    det.fit(data(5, 16))
    assert det.clusterer_.weights_.shape == (100, 16)
    assert det.synapse_.efficacy_.shape == (100,)
    assert det.clusterer_.current_radius() == 1 and det.clusterer_.current_learning_rate() == 0.25
    # the 8 grid neighbours of an inner unit, 3 of a corner
    assert len(det.clusterer_.match(det.clusterer_.weights_[55]).neighbours) == 8
    assert len(det.clusterer_.match(det.clusterer_.weights_[0]).neighbours) == 3


def test_make_habituating_by_names_equals_hsom():
    a = novelty.make("habituating", clusterer="som", synapse="stanley")
    b = novelty.make("hsom")
    assert a.get_params(deep=True).keys() == b.get_params(deep=True).keys()
    assert repr(a.get_params(deep=True)) == repr(b.get_params(deep=True))


def test_a_repeated_scan_descends_the_euler_sequence_to_0_0476():
    det = novelty.make("hsom")
    scan = np.full(16, 0.5)
    # 100 presentations: after about 120 the winner and its neighbours all sit within
    # an ulp of the scan (squared distances ~1e-31) and rounding, not the map, picks
    # the winner (a neighbour, whose efficacy is a little higher); see the next test.
    out = np.array([det.score_learn_one(scan) for _ in range(100)])
    assert out[0] == 1.0
    np.testing.assert_allclose(out, [euler(n) for n in range(100)], rtol=1e-12, atol=1e-15)
    assert [round(v, 4) for v in out[:4]] == [1.0, 0.6997, 0.4941, 0.3533]
    assert np.all(np.diff(out) <= 0)
    assert out.min() >= REST
    assert round(out[-1], 4) == 0.0476 and out[-1] == pytest.approx(REST, abs=1e-15)
    assert det.score_one(scan) == pytest.approx(REST, abs=1e-15)


def test_a_long_repeated_scan_never_goes_below_the_resting_value():
    det = novelty.make("hsom")
    scan = np.full(16, 0.5)
    out = np.array([det.score_learn_one(scan) for _ in range(400)])
    assert out.min() >= REST
    assert np.all(out[40:] < 0.048)  # 0.0476 once habituated, whichever unit wins the tie


def test_novelty_is_the_winners_efficacy_before_learning():
    det = small().fit(data(10))
    with damaging(det):
        det.synapse_.efficacy_[:] = np.linspace(0.1, 0.9, 20)
    x = data(1, seed=9)[0]
    winner = det.clusterer_.match(x).winner
    before = det.synapse_.efficacy_[winner]
    assert det.score_one(x) == before
    assert det.score_learn_one(x) == before
    assert det.synapse_.efficacy_[winner] < before  # learning happened after scoring


def test_neighbours_habituate_others_hold_inside_the_filter():
    det = novelty.make("hsom", n_rows=3, n_columns=3)
    det.fit(np.zeros((1, 2)))  # one scan learned; reset the bank for a clean count
    with damaging(det):
        det.synapse_.efficacy_[:] = 1.0
        det.clusterer_.weights_[:] = [[r, c] for r in range(3) for c in range(3)]
    det.score_learn_one(np.array([0.0, 0.0]))  # corner unit 0 wins
    eff = det.synapse_.efficacy_
    assert eff[0] == pytest.approx(1 - 1 / 3.33)
    np.testing.assert_allclose(eff[[1, 3, 4]], 1 - 1 / 14.3)
    np.testing.assert_array_equal(eff[[2, 5, 6, 7, 8]], 1.0)


# ----------------------------------------------------------- learning off
def test_learning_off_is_a_pure_function_of_the_state():
    det = small().fit(data())
    X = data(30, seed=1)
    before = state(det)
    a = det.novelty(X)
    b = det.stream(X, learn=False)
    c = np.array([det.score_one(x) for x in X])
    d = det.novelty(X)
    assert_same_state(before, state(det))
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(a, c)
    np.testing.assert_array_equal(a, d)
    rows, _ = det.clusterer_.winners(X)
    np.testing.assert_array_equal(a, det.synapse_.efficacy_[rows])
    a[:] = -1.0  # the returned array is the caller's, not the model's
    np.testing.assert_array_equal(det.novelty(X), d)


def test_score_samples_decision_function_predict_change_nothing():
    det = small().fit(data())
    before = state(det)
    X = data(10, seed=2)
    det.score_samples(X), det.decision_function(X), det.predict(X), det.winners(X)
    assert_same_state(before, state(det))


# ------------------------------------------------- streaming == batch learning
def test_score_learn_one_equals_stream_row_by_row():
    X = data(80)
    a, b = small(), small()
    out_a = a.stream(X)
    out_b = np.array([b.score_learn_one(x) for x in X])
    np.testing.assert_array_equal(out_a, out_b)
    assert_same_state(state(a), state(b))
    c = small()
    for x in X:
        assert c.learn_one(x) is c
    assert_same_state(state(a), state(c))


def test_partial_fit_equals_stream():
    X = data(50)
    a, b = small(), small()
    assert a.partial_fit(X) is a
    b.stream(X)
    assert_same_state(state(a), state(b))


def test_fit_resets_and_partial_fit_continues():
    X1, X2 = data(40, seed=1), data(40, seed=2)
    refit = small().fit(X1).fit(X2)
    fresh = small().fit(X2)
    assert_same_state(state(refit), state(fresh))
    continued = small().fit(X1).partial_fit(X2)
    at_once = small().partial_fit(np.vstack([X1, X2]))
    assert_same_state(state(continued), state(at_once))
    assert continued.clusterer_.n_updates_ == 80
    assert not np.array_equal(continued.clusterer_.weights_, fresh.clusterer_.weights_)


def test_fit_with_another_feature_count_starts_afresh():
    det = small().fit(data(10, d=4))
    det.fit(data(10, d=7))
    assert det.n_features_in_ == 7 and det.clusterer_.weights_.shape == (20, 7)


def test_n_epochs_is_repeated_passes():
    X = data(30)
    a = small(n_epochs=3).fit(X)
    b = small().fit(X).partial_fit(X).partial_fit(X)
    assert_same_state(state(a), state(b))
    assert a.clusterer_.n_updates_ == 90


def test_fit_does_not_touch_the_users_component_instances():
    som, syn = SOM(n_rows=3, n_columns=3), StanleySynapse()
    det = HabituatingFilter(clusterer=som, synapse=syn).fit(data(10))
    assert not hasattr(som, "weights_") and not hasattr(syn, "efficacy_")
    assert det.clusterer_ is not som and det.synapse_ is not syn


def test_timestamps_integrate_the_elapsed_time():
    scan = np.full((1, 3), 0.5)
    a = novelty.make("hsom", n_rows=2, n_columns=2)
    a.stream(scan, timestamps=[10.0])  # the first scan of a life is one step
    a.stream(scan, timestamps=[12.0])  # two steps' worth
    b = novelty.make("hsom", n_rows=2, n_columns=2)
    b.stream(np.vstack([scan, scan]))
    winner = b.clusterer_.match(scan[0]).winner
    assert a.synapse_.efficacy_[winner] == pytest.approx(euler(3), rel=1e-13)
    assert b.synapse_.efficacy_[winner] == pytest.approx(euler(2), rel=1e-13)
    assert a.last_time_ == 12.0


# ---------------------------------------------------- scikit-learn conventions
def test_score_samples_decision_function_and_predict_at_the_threshold():
    det = novelty.make("hsom", n_rows=1, n_columns=4, threshold=0.5).fit(np.zeros((1, 1)))
    with damaging(det):
        det.clusterer_.weights_[:] = [[0.0], [1.0], [2.0], [3.0]]
        det.synapse_.efficacy_[:] = [0.2, 0.5, 0.5000001, 0.9]
    X = np.array([[0.0], [1.0], [2.0], [3.0]])
    nov = det.novelty(X)
    np.testing.assert_array_equal(nov, [0.2, 0.5, 0.5000001, 0.9])
    np.testing.assert_array_equal(det.score_samples(X), -nov)
    np.testing.assert_allclose(det.decision_function(X), 0.5 - nov)
    assert det.offset_ == -0.5
    np.testing.assert_array_equal(np.sign(det.decision_function(X)), [1, 0, -1, -1])
    np.testing.assert_array_equal(det.predict(X), [1, 1, -1, -1])  # at the threshold: normal
    det.set_params(threshold=0.1)
    np.testing.assert_array_equal(det.predict(X), [-1, -1, -1, -1])


def test_fit_predict_and_clone():
    det = small(threshold=0.8)
    labels = det.fit_predict(data(20))
    assert set(np.unique(labels)) <= {-1, 1}
    twin = clone(det)
    assert not hasattr(twin, "n_features_in_")
    assert repr(twin.get_params(deep=True)) == repr(det.get_params(deep=True))


# ---------------------------------------------------------- determinism
def test_same_seed_same_outputs_different_seed_different_weights():
    X = data(50)
    a = novelty.make("hsom", random_state=11)
    b = novelty.make("hsom", random_state=11)
    c = novelty.make("hsom", random_state=12)
    np.testing.assert_array_equal(a.stream(X), b.stream(X))
    c.stream(X)
    assert_same_state(state(a), state(b))
    assert not np.array_equal(a.clusterer_.weights_, c.clusterer_.weights_)


def test_default_seed_makes_fit_reproducible():
    X = data(30)
    np.testing.assert_array_equal(small().fit(X).novelty(X), small().fit(X).novelty(X))


# ---------------------------------------------------------- properties
@st.composite
def filters_and_data(draw):
    params = {
        "n_rows": draw(st.integers(1, 4)),
        "n_columns": draw(st.integers(1, 4)),
        "learning_rate": draw(st.floats(0.0, 1.0)),
        "radius": draw(st.integers(0, 2)),
        "alpha": draw(st.floats(1.0, 3.0)),  # y0 = 1, alpha >= 1: rest = 1 - 1/alpha >= 0
        "others": draw(st.sampled_from(["hold", "forget"])),
        "method": draw(st.sampled_from(["euler", "exact"])),
        "stimulus": draw(st.floats(0.0, 1.0)),
        "random_state": draw(st.integers(0, 2**16)),
    }
    low = params["alpha"] if params["method"] == "euler" else 0.1
    params["tau_winner"] = draw(st.floats(low, 30.0))
    params["tau_neighbour"] = draw(st.floats(low, 30.0))
    n_features = draw(st.integers(1, 4))
    X = draw(hnp.arrays(np.float64, (draw(st.integers(1, 40)), n_features),
                        elements=st.floats(-5, 5, allow_nan=False)))
    return novelty.make("hsom", **params), X


@settings(max_examples=40, deadline=None)
@given(filters_and_data())
def test_novelty_lies_in_0_1(case):
    det, X = case
    out = det.stream(X)
    out2 = det.stream(X[::-1])
    nov = det.novelty(X)
    for values in (out, out2, nov):
        assert np.all((values >= 0.0) & (values <= 1.0))
    assert out[0] == 1.0  # the first scan of a fresh filter is fully novel


# ------------------------------------------------ habituation x mismatch (ours)
def mismatch(**params):
    return novelty.make("hsom", n_rows=2, n_columns=2, novelty_rule="mismatch", **params)


def test_mismatch_rule_by_hand():
    det = mismatch(match_scale=0.5).fit(data(10, 2))
    with damaging(det):
        det.clusterer_.weights_[:] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]
        det.synapse_.efficacy_[:] = [0.25, 1.0, 0.5, 0.0]
    X = np.array([[0.0, 0.0], [0.0, 0.25], [0.9, 1.0], [0.6, 0.0]])
    # winners 0, 0, 3, 1; d^2 = 0, 1/16, 1/100, 4/25; sigma^2 = 1/4
    expected = [0.25, 1 - 0.75 * np.exp(-0.125), 1 - np.exp(-0.02), 1.0]
    np.testing.assert_allclose(det.novelty(X), expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose([det.score_one(x) for x in X], expected, rtol=0, atol=1e-15)


def test_product_rule_by_hand():
    det = mismatch(match_scale=0.5).set_params(novelty_rule="product").fit(data(10, 2))
    with damaging(det):
        det.clusterer_.weights_[:] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]
        det.synapse_.efficacy_[:] = [0.25, 1.0, 0.5, 0.0]
    X = np.array([[0.0, 0.0], [0.0, 0.25], [0.9, 1.0], [0.6, 0.0]])
    # winners 0, 0, 3, 1; d^2 = 0, 1/16, 1/100, 4/25; sigma^2 = 1/4: y (1 - exp(-2 d^2))
    expected = [0.0, 0.25 * (1 - np.exp(-0.125)), 0.0, 1 - np.exp(-0.32)]
    np.testing.assert_allclose(det.novelty(X), expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose([det.score_one(x) for x in X], expected, rtol=0, atol=1e-15)
    assert det.resting_novelty == 0.0  # an exact match: no mismatch


def test_product_rule_while_learning_a_repeated_scan():
    """Learning on: the efficacy before the scan is learned times the mismatch to the winner then."""
    det = mismatch(match_scale=0.5, radius=0).set_params(novelty_rule="product").fit(data(10, 2))
    with damaging(det):
        det.clusterer_.weights_[:] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]
        det.synapse_.efficacy_[:] = 1.0
    x = np.array([0.0, 0.5])
    out = [det.score_learn_one(x) for _ in range(3)]
    # unit 0 wins each time and moves a quarter of the way: d = 0.5, 0.375, 0.28125
    d = [0.5, 0.375, 0.28125]
    expected = [euler(k) * (1 - np.exp(-2 * d[k] ** 2)) for k in range(3)]
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-15)


def test_efficacy_rule_is_the_default_and_keeps_no_calibration():
    det = small().fit(data())
    assert det.novelty_rule == "efficacy" and det.match_scale_ is None
    assert not hasattr(det, "calibration_scans_")


def test_a_given_match_scale_is_used_as_is():
    det = mismatch(match_scale=0.7).fit(data())
    assert det.match_scale_ == 0.7 and not hasattr(det, "calibration_scans_")


@pytest.mark.parametrize("name,params", [
    ("hsom", {"novelty_rule": "mismatch", "calibration_scans": 30}),
    ("gwr-novelty", {"novelty_rule": "mismatch", "activity_threshold": "auto",
                     "firing_condition": False, "new_unit_wins": True}),
    ("gng-stanley", {"novelty_rule": "mismatch", "insertion_interval": 5}),
    ("gwr-explore", {}),
])
def test_frozen_novelty_is_what_learning_the_scan_would_report(name, params):
    X, probe = data(60), data(15, seed=2) * 1.5
    det = novelty.make(name, **params).fit(X)
    frozen = det.novelty(probe)
    learned = [clone_fitted(det).score_learn_one(x) for x in probe]
    np.testing.assert_array_equal(frozen, learned)


def clone_fitted(det):
    return copy.deepcopy(det)


def test_mismatch_rule_parameters_are_checked():
    for params, message in [({"novelty_rule": "distance"}, "novelty_rule"),
                            ({"match_scale": 0.0}, "match_scale"),
                            ({"match_quantile": 1.5}, "match_quantile"),
                            ({"calibration_scans": 1}, "calibration_scans")]:
        with pytest.raises(ValueError, match=f"The '{message}' parameter of HabituatingFilter"):
            small(**params).fit(data())


# ------------------------------------------------------------ the novelty range
@pytest.mark.parametrize("params", [dict(stimulus=2.0), dict(synapse__alpha=0.5), dict(y0=1e12), dict(y0=1.5)])
def test_parameters_whose_efficacy_leaves_0_1_are_refused(params):
    det = small(**params)
    with pytest.raises(ValueError, match=r"efficacy is the novelty, on \[0, 1\].*S <= alpha \* y0"):
        det.learn_one(np.full(4, 0.5))
    assert not hasattr(det, "n_features_in_")
    with pytest.raises(ValueError, match=r"on \[0, 1\]"):
        det.fit(data())


def test_a_named_synapse_is_checked_again_under_another_stimulus_or_factory():
    """The range of a synapse given by its registered name is checked once per name, factory
    and stimulus (building it at every call cost a third of a one-scan stream): a stimulus
    set after a call that passed is refused as before, and so is a name registered anew."""
    from novelty import registry
    from novelty.habituation import StanleySynapse

    det = novelty.HabituatingFilter(clusterer="som", synapse="stanley").fit(data())
    det.stream(data()[:3])
    det.stimulus = 2.0
    with pytest.raises(ValueError, match=r"efficacy is the novelty, on \[0, 1\]"):
        det.stream(data()[:3])
    det.stimulus = 1.0
    det.stream(data()[:3])

    class Unbounded(StanleySynapse):  # its efficacy rises past 1 (y0 = 2)
        def __init__(self, **params):
            super().__init__(**{"y0": 2.0, **params})

    registry.synapses.register("test-renamed-synapse", StanleySynapse)
    try:
        det = novelty.HabituatingFilter(clusterer="som", synapse="test-renamed-synapse").fit(data())
        det.stream(data()[:3])
        registry.synapses.register("test-renamed-synapse", Unbounded, replace=True)
        with pytest.raises(ValueError, match=r"efficacy is the novelty, on \[0, 1\]"):
            det._validate_params()
    finally:
        registry.synapses.unregister("test-renamed-synapse")


@pytest.mark.parametrize("params", [dict(stimulus=1.05), dict(y0=0.5, alpha=2.0), dict(stimulus=0.0)])
def test_at_the_edge_of_the_range_novelty_stays_in_it(params):
    # Stanley's fixed point y0 - S/alpha >= 0: S = alpha y0 settles at exactly 0, never below
    det = small(**params)
    scan = np.full(4, 0.5)
    novelties = np.array([det.score_learn_one(scan) for _ in range(200)])
    assert novelties.min() >= -1e-12 and novelties.max() <= 1.0


@pytest.mark.parametrize("written", [-1.0, 2.0, 1e308])
def test_an_efficacy_written_in_place_outside_its_range_is_refused_in_every_call(written):
    # learning keeps the efficacy in [y0 - S / alpha, y0]; a value written into efficacy_ is not the novelty
    X = np.random.default_rng(0).random((20, 4))
    for call in ("novelty", "score_one", "score_learn_one", "stream", "predict"):
        det = novelty.make("hsom", n_rows=2, n_columns=2).fit(X)
        with damaging(det):
            det.synapse_.efficacy_[:] = written
        before = det.synapse_.efficacy_.copy()
        message = (r"outside the \[0.047619, 1\] its synapse keeps" if abs(written) <= 1e100
                   else r"efficacy_ holds a value beyond 1e\+100")  # refused before the call reads it
        with pytest.raises(StateError, match=message):
            getattr(det, call)(X if call in ("novelty", "stream", "predict") else X[0])
        if call not in ("score_learn_one", "stream"):   # the learning calls learned before the novelty was read
            np.testing.assert_array_equal(det.synapse_.efficacy_, before)
