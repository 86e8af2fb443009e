"""Time-aware habituation and the forgetting rule, for every synapse model.

With timestamps, a synapse integrates over the elapsed time dt: the winning
neighbourhood is stimulated for dt, the other units (with others="forget")
rest for dt. One step per scan (dt = 1) is the default.
"""

import math

import numpy as np
import pytest
from sklearn.base import clone

import novelty
from novelty.habituation import StanleySynapse, WangHsuSynapse

NONE = np.empty(0, dtype=np.intp)
MODELS = {"stanley": StanleySynapse, "wang-hsu": WangHsuSynapse}


def _state(syn):
    return [getattr(syn, name).copy() for name in type(syn)._per_unit]


def _drive(syn, schedule):
    """Apply (winner, neighbours, stimulus, dt) steps."""
    for winner, neighbours, s, dt in schedule:
        syn.step(winner, np.array(neighbours, dtype=np.intp), stimulus=s, dt=dt)
    return syn


SCHEDULE = [(0, [1], 1.0, 1.0), (2, [1, 3], 1.0, 1.0), (0, [], 0.6, 1.0), (3, [2], 1.0, 1.0)]


# ------------------------------------------------------------ dt = 2 vs 2 x 1
def test_stanley_exact_dt2_equals_two_exact_unit_steps():
    one = StanleySynapse(method="exact", others="forget").initialize(4)
    two = clone(one).initialize(4)
    _drive(one, SCHEDULE[:2])
    _drive(two, SCHEDULE[:2])
    one.step(0, np.array([1]), dt=2.0)
    two.step(0, np.array([1]), dt=1.0)
    two.step(0, np.array([1]), dt=1.0)
    assert np.allclose(one.efficacy_, two.efficacy_, rtol=0, atol=1e-15)
    # and both are the closed form y_inf + (y - y_inf) exp(-alpha dt / tau) for the winner
    y = StanleySynapse(method="exact").initialize(1)
    y.step(0, NONE, dt=2.0)
    y_inf = 1 - 1 / 1.05
    assert y.efficacy_[0] == pytest.approx(y_inf + (1 - y_inf) * math.exp(-1.05 * 2 / 3.33), rel=1e-15)


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("others", ["hold", "forget"])
def test_euler_dt2_equals_two_unit_steps_bit_for_bit(name, others):
    one = MODELS[name](others=others).initialize(4)
    two = clone(one).initialize(4)
    _drive(one, SCHEDULE)
    _drive(two, SCHEDULE)
    one.step(1, np.array([0, 2]), dt=2.0)
    two.step(1, np.array([0, 2]), dt=1.0)
    two.step(1, np.array([0, 2]), dt=1.0)
    for a, b in zip(_state(one), _state(two)):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("others", ["hold", "forget"])
def test_exact_dt2_equals_two_unit_steps(name, others):
    one = MODELS[name](method="exact", others=others).initialize(4)
    two = clone(one).initialize(4)
    _drive(one, SCHEDULE)
    _drive(two, SCHEDULE)
    one.step(1, np.array([0, 2]), stimulus=0.7, dt=2.0)
    two.step(1, np.array([0, 2]), stimulus=0.7, dt=1.0)
    two.step(1, np.array([0, 2]), stimulus=0.7, dt=1.0)
    for a, b in zip(_state(one), _state(two)):
        assert np.allclose(a, b, rtol=0, atol=1e-14)


@pytest.mark.parametrize("name", MODELS)
def test_a_longer_interval_habituates_the_winner_more(name):
    short = MODELS[name](method="exact").initialize(1)
    long = clone(short).initialize(1)
    short.step(0, NONE, dt=0.5)
    long.step(0, NONE, dt=3.0)
    assert long.efficacy_[0] < short.efficacy_[0] < 1.0


# ------------------------------------------------------------ forgetting rule
@pytest.mark.parametrize("method", ["euler", "exact"])
@pytest.mark.parametrize("name", MODELS)
def test_forgetting_recovers_every_unstimulated_synapse(name, method):
    syn = MODELS[name](method=method, others="forget").initialize(3)
    for _ in range(15):
        syn.step(0, np.array([1]))
    previous = syn.efficacy_[:2].copy()
    assert np.all(previous < 0.9)
    for _ in range(40):
        syn.step(2, NONE)
        now = syn.efficacy_[:2]
        assert np.all(now > previous), "an unstimulated synapse recovers at every step"
        assert np.all(now <= syn.y0)
        previous = now.copy()
    assert syn.efficacy_[2] < 1.0, "the winner habituates meanwhile"


@pytest.mark.parametrize("name", MODELS)
def test_hold_keeps_every_unstimulated_synapse(name):
    syn = MODELS[name](others="hold").initialize(3)
    for _ in range(15):
        syn.step(0, np.array([1]))
    before = _state(syn)
    for _ in range(10):
        syn.step(2, NONE)
    after = _state(syn)
    for a, b in zip(before, after):
        assert np.array_equal(a[:2], b[:2])


def test_forgetting_uses_tau_forget_stanley():
    syn = StanleySynapse(method="exact", others="forget", tau_forget=5.0).initialize(2)
    for _ in range(6):
        syn.step(0, NONE)
    y = syn.efficacy_[0]
    syn.step(1, NONE, dt=3.0)
    assert syn.efficacy_[0] == pytest.approx(1 + (y - 1) * math.exp(-1.05 * 3.0 / 5.0), rel=1e-15)


def test_forgetting_uses_tau_forget_and_the_learned_recovery_speed_wang_hsu():
    syn = WangHsuSynapse(method="exact", others="forget", tau_forget=5.0).initialize(2)
    for _ in range(6):
        syn.step(0, NONE)
    y, z = syn.efficacy_[0], syn.recovery_[0]
    syn.step(1, NONE, dt=3.0)
    assert syn.efficacy_[0] == pytest.approx(1 + (y - 1) * math.exp(-1.05 * z * 3.0 / 5.0), rel=1e-14)
    assert syn.recovery_[0] == z


# --------------------------------------------------------- detector timestamps
A, B = np.zeros(4), np.ones(4)


def _alternating(spacing, others, synapse, n=10):
    """A, B, A, B, ... with the given time between scans; A's novelty at each presentation."""
    det = novelty.make("habituating", clusterer="som", synapse=synapse, n_rows=1, n_columns=2, radius=0,
                       method="exact", others=others)
    X = np.array([A, B] * n)
    novelty_ = det.stream(X, timestamps=np.arange(2 * n) * float(spacing))
    rows, _ = det.winners(np.array([A, B]))
    assert rows[0] != rows[1], "A and B must win different units for this test"
    return novelty_[0::2]


def test_stanley_scans_far_apart_habituate_less_with_forgetting():
    close = _alternating(1, "forget", "stanley")
    far = _alternating(10, "forget", "stanley")
    assert close[0] == far[0] == 1.0
    assert far[1] > close[1], "A's unit recovers while B is seen for longer"
    # Each presentation also stimulates A's unit for longer, but the balance
    # of 10 units of stimulus and 10 of rest settles far higher (0.553 vs 0.279).
    assert np.all(far[3:] > close[3:]) and np.all(far[5:] > close[5:] + 0.1)
    assert far[-1] == pytest.approx(0.553, abs=1e-3) and close[-1] == pytest.approx(0.279, abs=1e-3)


def test_stanley_without_forgetting_elapsed_time_only_lengthens_the_stimulus():
    close = _alternating(1, "hold", "stanley")
    far = _alternating(10, "hold", "stanley")
    assert np.all(far[2:] < close[2:])


def test_wang_hsu_scans_far_apart_recover_but_build_long_term_memory():
    close = _alternating(1, "forget", "wang-hsu")
    far = _alternating(10, "forget", "wang-hsu")
    assert np.all(far[1:5] > close[1:5]), "early on, A's unit recovers between presentations"
    # Each presentation stimulates A's unit for 10 time units, which lowers z:
    # after enough of them the long-term memory outweighs the recovery.
    assert far[-1] < close[-1]


@pytest.mark.parametrize("synapse", ["stanley", "wang-hsu"])
def test_fit_stream_and_learn_one_agree_with_timestamps(synapse):
    rng = np.random.default_rng(3)
    X = rng.random((40, 4))
    t = np.cumsum(rng.exponential(2.0, size=40))
    params = dict(clusterer="som", synapse=synapse, n_rows=3, n_columns=3, method="exact", others="forget")
    fitted = novelty.make("habituating", **params).fit(X, timestamps=t)
    streamed = novelty.make("habituating", **params)
    out = streamed.stream(X, timestamps=t)
    one = novelty.make("habituating", **params)
    out_one = np.array([one.score_learn_one(x, t=ti) for x, ti in zip(X, t)])
    assert np.allclose(out, out_one, rtol=0, atol=1e-14)
    for det in (streamed, one):
        for a, b in zip(_state(fitted.synapse_), _state(det.synapse_)):
            assert np.allclose(a, b, rtol=0, atol=1e-14)
    assert fitted.last_time_ == streamed.last_time_ == one.last_time_ == t[-1]
    untimed = novelty.make("habituating", **params).fit(X)
    assert not np.allclose(untimed.synapse_.efficacy_, fitted.synapse_.efficacy_), "the timestamps matter"
