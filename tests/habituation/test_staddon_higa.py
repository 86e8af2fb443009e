"""Staddon & Higa's two-unit cascade: hand-computed steps, closed forms, properties, long gaps.

F <- a_f F + b_f S,  L <- a_s L + b_s max(0, S - F),  y = max(0, y0 - F - L), with
a_f = 1 - 1/tau, b_f = c_f/tau, a_s = 1 - 1/(r tau), b_s = c_s/(r tau) for a step of one scan.
Defaults: tau 3.33 / 14.3, c_f 0.8, c_s 0.8, r 10, y0 1.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.base import clone

import novelty
from novelty._component import StateError
from novelty.habituation import StaddonHigaSynapse, StanleySynapse
from novelty.habituation.staddon_higa import MAX_STEPS, cascade_steps

NONE = np.empty(0, dtype=np.intp)


def closed_form(n, tau=3.33, c_f=0.8, c_s=0.8, r=10.0, s=1.0, y0=1.0):
    """Equations (5)-(6) of the module: (F, L, y) after n steps from a fresh synapse."""
    a_f, a_s, b_s = 1 - 1 / tau, 1 - 1 / (r * tau), c_s / (r * tau)
    fast = c_f * s * (1 - a_f**n)
    slow = c_s * (1 - c_f) * s * (1 - a_s**n) + b_s * c_f * s * (a_s**n - a_f**n) / (a_s - a_f)
    return fast, slow, max(0.0, y0 - fast - slow)


def winner_steps(syn, n, **kw):
    out = []
    for _ in range(n):
        syn.step(0, NONE, **kw)
        out.append(float(syn.efficacy_[0]))
    return out


# ------------------------------------------------------------ hand computation
def test_first_two_steps_by_hand():
    syn = StaddonHigaSynapse().initialize(3)
    syn.step(0, np.array([1]))
    # winner: F = 0.8/3.33, L = (0.8/33.3) * max(0, 1 - 0); neighbour: tau 14.3
    assert syn.fast_memory_[0] == pytest.approx(0.8 / 3.33, abs=1e-15)
    assert syn.slow_memory_[0] == pytest.approx(0.8 / 33.3, abs=1e-15)
    assert syn.efficacy_[0] == pytest.approx(1 - 0.8 / 3.33 - 0.8 / 33.3, abs=1e-15)
    assert round(float(syn.efficacy_[0]), 6) == 0.735736
    assert syn.fast_memory_[1] == pytest.approx(0.8 / 14.3, abs=1e-15)
    assert syn.slow_memory_[1] == pytest.approx(0.8 / 143.0, abs=1e-15)
    assert (syn.efficacy_[2], syn.fast_memory_[2], syn.slow_memory_[2]) == (1.0, 0.0, 0.0)  # others hold
    syn.step(0, np.array([1]))
    # F2 = (1 - 1/3.33) F1 + 0.8/3.33; L2 = (1 - 1/33.3) L1 + (0.8/33.3)(1 - F1): the old F
    f1, l1 = 0.8 / 3.33, 0.8 / 33.3
    assert syn.fast_memory_[0] == pytest.approx((1 - 1 / 3.33) * f1 + 0.8 / 3.33, abs=1e-15)
    assert syn.slow_memory_[0] == pytest.approx((1 - 1 / 33.3) * l1 + (0.8 / 33.3) * (1 - f1), abs=1e-15)
    assert round(float(syn.efficacy_[0]), 6) == 0.550109


def test_one_step_is_the_difference_equation_bit_for_bit():
    syn = StaddonHigaSynapse(fast_gain=0.7, slow_gain=0.5, slowness=4.0, tau_winner=2.5).initialize(1)
    f = s = 0.0
    for stimulus in (0.8, 0.8, 0.3, 0.0, 1.0):
        syn.step(0, NONE, stimulus=stimulus)
        f, s = (1 - 1 / 2.5) * f + (0.7 / 2.5) * stimulus, (1 - 1 / 10.0) * s + (0.5 / 10.0) * max(0.0, stimulus - f)
        assert (syn.fast_memory_[0], syn.slow_memory_[0]) == (f, s)
        assert syn.efficacy_[0] == max(0.0, 1.0 - f - s)


def test_the_threshold_cuts_the_slow_memory_off_when_the_fast_one_exceeds_the_stimulus():
    syn = StaddonHigaSynapse().initialize(1)
    winner_steps(syn, 20)  # F near 0.8
    slow = float(syn.slow_memory_[0])
    syn.step(0, NONE, stimulus=0.5)  # X = max(0, 0.5 - F) = 0: the slow memory only decays
    assert syn.slow_memory_[0] == (1 - 1 / 33.3) * slow


# ------------------------------------------------------------ closed forms
def test_constant_stimulus_follows_the_closed_form():
    syn = StaddonHigaSynapse().initialize(1)
    for n, y in enumerate(winner_steps(syn, 120), start=1):
        fast, slow, expected = closed_form(n)
        assert y == pytest.approx(expected, rel=1e-12, abs=1e-14)
    assert syn.fast_memory_[0] == pytest.approx(closed_form(120)[0], rel=1e-12)
    assert syn.slow_memory_[0] == pytest.approx(closed_form(120)[1], rel=1e-12)


def test_resting_efficacy_is_the_limit_of_the_closed_form():
    syn = StaddonHigaSynapse()
    assert syn.resting_efficacy == pytest.approx(1 - 0.8 - 0.8 * 0.2, abs=1e-15)
    assert closed_form(5000)[2] == pytest.approx(syn.resting_efficacy, abs=1e-12)
    assert StaddonHigaSynapse(fast_gain=1.0, slow_gain=3.0).resting_efficacy == 0.0
    assert StaddonHigaSynapse(fast_gain=0.5, slow_gain=3.0).resting_efficacy == 0.0  # floored


def test_without_a_slow_memory_it_is_stanleys_synapse_with_alpha_1():
    cascade = StaddonHigaSynapse(slow_gain=0.0, fast_gain=1 / 1.05).initialize(1)
    stanley = StanleySynapse(alpha=1.0).initialize(1)
    for _ in range(30):
        cascade.step(0, NONE)
        stanley.step(0, NONE, stimulus=1 / 1.05)
        assert cascade.efficacy_[0] == pytest.approx(stanley.efficacy_[0], rel=1e-13)


def test_recovery_without_stimulus_is_geometric():
    syn = StaddonHigaSynapse(others="forget", tau_forget=5.0).initialize(2)
    winner_steps(syn, 15)
    fast, slow = float(syn.fast_memory_[0]), float(syn.slow_memory_[0])
    for n in range(1, 40):
        syn.step(1, NONE)
        assert syn.fast_memory_[0] == pytest.approx(fast * (1 - 1 / 5) ** n, rel=1e-12)
        assert syn.slow_memory_[0] == pytest.approx(slow * (1 - 1 / 50) ** n, rel=1e-12)


# ------------------------------------------------------------ two time scales
def _recovered_after(train_steps, gap, spaced=False):
    """Efficacy of a forgetting synapse `gap` scans after training (massed, or one scan in 5)."""
    syn = StaddonHigaSynapse(others="forget", tau_forget=5.0).initialize(2)
    for i in range(train_steps):
        syn.step(0 if (not spaced or i % 5 == 0) else 1, NONE)
    for _ in range(gap):
        syn.step(1, NONE)
    return float(syn.efficacy_[0])


def test_recovery_is_slower_the_longer_the_training():
    assert _recovered_after(5, 30) > _recovered_after(40, 30) + 0.02  # 0.960 against 0.926


def test_recovery_is_slower_after_spaced_training_than_after_massed():
    # as many stimuli either way: massed leaves mostly fast memory, spaced more slow memory
    massed = StaddonHigaSynapse(others="forget", tau_forget=5.0).initialize(2)
    spaced = clone(massed).initialize(2)
    for _ in range(8):
        massed.step(0, NONE)
    for i in range(40):
        spaced.step(0 if i % 5 == 0 else 1, NONE)
    assert spaced.slow_memory_[0] > massed.slow_memory_[0]
    for _ in range(30):
        massed.step(1, NONE)
        spaced.step(1, NONE)
    assert spaced.efficacy_[0] < massed.efficacy_[0]


def test_stanley_recovers_alike_whatever_the_training():
    # the contrast: a single integrator, trained to the same level, forgets at one rate
    a = StanleySynapse(others="forget", tau_forget=5.0).initialize(2)
    b = clone(a).initialize(2)
    for _ in range(40):
        a.step(0, NONE)
    for _ in range(400):
        b.step(0, NONE)
    for _ in range(30):
        a.step(1, NONE)
        b.step(1, NONE)
    assert a.efficacy_[0] == pytest.approx(b.efficacy_[0], abs=1e-9)


# ------------------------------------------------------------ properties
gains = st.fixed_dictionaries({
    "fast_gain": st.floats(0.05, 1.0),
    "slow_gain": st.floats(0.0, 2.0),
    "slowness": st.floats(1.0, 50.0),
    "tau_winner": st.floats(1.0, 30.0),
})


@settings(max_examples=40, deadline=None)
@given(gains, st.lists(st.tuples(st.integers(0, 2), st.floats(0.0, 1.0), st.sampled_from([0.5, 1.0, 2.5])),
                       min_size=1, max_size=40), st.sampled_from(["hold", "forget"]))
def test_efficacy_and_memories_stay_in_bounds(params, seq, others):
    syn = StaddonHigaSynapse(others=others, **params).initialize(3)
    low, high = syn.efficacy_range(1.0)
    for winner, stimulus, dt in seq:
        syn.step(winner, NONE, stimulus=stimulus, dt=dt)
        assert np.all(syn.efficacy_ >= low) and np.all(syn.efficacy_ <= high)
        assert np.all(syn.fast_memory_ >= 0) and np.all(syn.fast_memory_ <= params["fast_gain"] + 1e-12)
        assert np.all(syn.slow_memory_ >= 0) and np.all(syn.slow_memory_ <= params["slow_gain"] + 1e-12)
    syn._check_state()


@settings(max_examples=40, deadline=None)
@given(gains, st.floats(0.01, 1.0), st.integers(1, 150))
def test_monotone_decrease_under_a_constant_stimulus(params, s, n):
    # sufficient for no overshoot of the slow memory: r >= 1 / (1 - c_f) (module docstring)
    params["slowness"] = max(params["slowness"], 1 / max(1e-9, 1 - params["fast_gain"]))
    syn = StaddonHigaSynapse(**params).initialize(1)
    ys = [1.0] + winner_steps(syn, n, stimulus=s)
    assert all(b <= a + 1e-15 for a, b in zip(ys, ys[1:]))


@settings(max_examples=30, deadline=None)
@given(gains, st.integers(1, 30), st.integers(1, 60))
def test_recovery_in_absence(params, train, gap):
    syn = StaddonHigaSynapse(others="forget", tau_forget=params["tau_winner"], **params).initialize(2)
    winner_steps(syn, train)
    ys = [float(syn.efficacy_[0])]
    for _ in range(gap):
        syn.step(1, NONE)
        ys.append(float(syn.efficacy_[0]))
    assert all(b >= a for a, b in zip(ys, ys[1:]))
    assert ys[-1] <= syn.y0


# ------------------------------------------------------------ long gaps
@pytest.mark.parametrize("stimulus", [0.0, 0.4, 1.0])
@pytest.mark.parametrize("start", [(0.0, 0.0), (0.7, 0.3), (0.1, 0.6)])
def test_a_long_gap_is_the_loop_to_rounding(stimulus, start, monkeypatch):
    dt = 3000.0
    args = (stimulus, 40.0, dt, 0.8, 0.8, 30.0)
    closed = cascade_steps(*start, *args)
    monkeypatch.setattr("novelty.habituation.staddon_higa.MAX_STEPS", 10**6)
    looped = cascade_steps(*start, *args)
    np.testing.assert_allclose(closed, looped, rtol=1e-11, atol=1e-15)


def test_a_huge_gap_takes_few_steps_and_settles():
    f, s = cascade_steps(0.5, 0.2, 1.0, 3.33, 1e300, 0.8, 0.8, 10.0)
    assert (f, s) == pytest.approx((0.8, 0.8 * 0.2), rel=1e-12)
    assert cascade_steps(0.5, 0.2, 0.0, 3.33, 1e300, 0.8, 0.8, 10.0) == (0.0, 0.0)
    assert MAX_STEPS == 1024


# ------------------------------------------------------------ bank, state, files
def test_grow_and_shrink_carry_the_three_state_arrays():
    syn = StaddonHigaSynapse().initialize(3)
    syn.step(1, NONE)
    syn.shrink(np.array([0]))
    syn.grow(1)
    assert syn.fast_memory_.tolist() == [0.8 / 3.33, 0.0, 0.0]
    assert syn.efficacy_.shape == syn.slow_memory_.shape == (3,)


@pytest.mark.parametrize("attribute, value", [("fast_memory_", -0.1), ("slow_memory_", np.nan),
                                              ("efficacy_", 0.5), ("slow_memory_", np.inf)])
def test_state_check_refuses_an_impossible_state(attribute, value):
    syn = StaddonHigaSynapse().initialize(2)
    getattr(syn, attribute)[0] = value
    with pytest.raises(StateError):
        syn._check_state()


def test_saved_filter_keeps_both_memories(tmp_path):
    det = novelty.make("habituating", clusterer="som", synapse="staddon-higa", others="forget", n_rows=3,
                     n_columns=3).fit(np.random.default_rng(0).random((60, 4)))
    det.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    for name in ("efficacy_", "fast_memory_", "slow_memory_"):
        np.testing.assert_array_equal(getattr(back.synapse_, name), getattr(det.synapse_, name))
    x = np.random.default_rng(1).random((5, 4))
    np.testing.assert_array_equal(back.stream(x), det.stream(x))


@pytest.mark.parametrize("params, match", [
    ({"fast_gain": 0.0}, "fast_gain"), ({"fast_gain": 1.5}, "fast_gain"), ({"slow_gain": -1}, "slow_gain"),
    ({"slowness": 0.5}, "slowness"), ({"tau_winner": 0.5}, "tau_winner"), ({"tau_forget": 0.9}, "tau_forget"),
])
def test_invalid_parameters_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        StaddonHigaSynapse(**params).initialize(1)


def test_compiled_equals_reference_with_forgetting():
    from novelty.testing.compiled_checks import check_compiled_equals_reference

    check_compiled_equals_reference(StaddonHigaSynapse(others="forget", tau_forget=4.0, fast_gain=0.6,
                                                        slow_gain=1.2, slowness=3.0))
