"""Wang & Hsu's synapse: hand-computed steps, long-term memory, bounds, bank, dt.

tau dy/dt = alpha z (y0 - y) - beta y S,   dz/dt = gamma z (z - l) S.
Defaults: tau 3.33 / 14.3, alpha 1.05, beta 2, gamma 0.05, y0 1, z0 0.9, l 1.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from sklearn.base import clone

import novelty
from novelty._component import StateError
from novelty.habituation import StanleySynapse, WangHsuSynapse, wang_hsu

NONE = np.empty(0, dtype=np.intp)


# ------------------------------------------------------------ hand computation
def test_first_euler_steps_by_hand():
    syn = WangHsuSynapse().initialize(3)
    syn.step(0, np.array([1]))
    # winner: y = 1 + (1/3.33)(1.05 * 0.9 * 0 - 2 * 1); z = 0.9 + 0.05 * 0.9 * (0.9 - 1)
    assert syn.efficacy_[0] == pytest.approx(1 - 2 / 3.33, abs=1e-15)
    assert syn.efficacy_[0] == pytest.approx(0.399399, abs=1e-6)
    assert syn.recovery_[0] == pytest.approx(0.8955, abs=1e-15)
    # neighbour: same stimulus, tau = 14.3 for y; z has no tau, so it falls alike
    assert syn.efficacy_[1] == pytest.approx(1 - 2 / 14.3, abs=1e-15)
    assert syn.recovery_[1] == pytest.approx(0.8955, abs=1e-15)
    # others="hold": unit 2 untouched
    assert (syn.efficacy_[2], syn.recovery_[2]) == (1.0, 0.9)
    syn.step(0, np.array([1]))
    # y2 = y1 + (1/3.33)(1.05 * 0.8955 * (1 - y1) - 2 * y1); z2 = 0.8955 + 0.05 * 0.8955 * (0.8955 - 1)
    assert syn.efficacy_[0] == pytest.approx(0.3291084, abs=1e-7)
    assert syn.recovery_[0] == pytest.approx(0.8908210125, abs=1e-12)


def test_euler_step_is_equation_6_bit_for_bit():
    syn = WangHsuSynapse(alpha=0.7, beta=1.3, gamma=0.2, z0=0.6, l=1.5, tau_winner=5.0).initialize(1)
    y, z = 1.0, 0.6
    for _ in range(5):
        syn.step(0, NONE, stimulus=0.8)
        y, z = y + (1 / 5.0) * (0.7 * z * (1 - y) - 1.3 * y * 0.8), z + 0.2 * z * (z - 1.5) * 0.8
        assert syn.efficacy_[0] == y and syn.recovery_[0] == z


def test_resting_efficacy():
    assert WangHsuSynapse().resting_efficacy == 0.0  # z falls to 0 under a long stimulus
    frozen = WangHsuSynapse(gamma=0.0)  # no long-term memory: Stanley-like floor
    assert frozen.resting_efficacy == pytest.approx(1.05 * 0.9 / (1.05 * 0.9 + 2.0))
    syn = frozen.initialize(1)
    for _ in range(300):
        syn.step(0, NONE)
    assert syn.efficacy_[0] == pytest.approx(frozen.resting_efficacy, abs=1e-12)


# ------------------------------------------------------------ long-term memory
def reexposure(synapse, exposure=20, rest=200, level=0.3, recover="forget"):
    """Scans to fall below ``level`` on a first and a second exposure, and the efficacy in between.

    Unit 0 is stimulated for ``exposure`` scans, then receives S = 0 for
    ``rest`` scans (``"forget"``: another unit wins and the others rule
    forgets; ``"direct"``: unit 0 itself gets stimulus 0), then is
    stimulated again.
    """
    bank = clone(synapse).set_params(others="forget").initialize(2)
    first = None
    for n in range(1, exposure + 1):
        bank.step(0, NONE)
        if first is None and bank.efficacy_[0] < level:
            first = n
    for _ in range(rest):
        if recover == "forget":
            bank.step(1, NONE)
        else:
            bank.step(0, NONE, stimulus=0.0)
    start = float(bank.efficacy_[0])
    for n in range(1, 200):
        bank.step(0, NONE)
        if bank.efficacy_[0] < level:
            return first, n, start
    return first, None, start


LTM_CASES = [
    pytest.param(WangHsuSynapse(), id="wang-hsu-euler"),
    pytest.param(WangHsuSynapse(method="exact"), id="wang-hsu-exact"),
    pytest.param(StanleySynapse(), id="stanley-euler",
                 marks=pytest.mark.xfail(strict=True, reason="Stanley's synapse has no long-term memory")),
    pytest.param(StanleySynapse(method="exact"), id="stanley-exact",
                 marks=pytest.mark.xfail(strict=True, reason="Stanley's synapse has no long-term memory")),
]


@pytest.mark.parametrize("recover", ["forget", "direct"])
@pytest.mark.parametrize("synapse", LTM_CASES)
def test_second_exposure_habituates_faster_after_full_recovery(synapse, recover):
    first, second, start = reexposure(synapse, recover=recover)
    assert start > 0.99, "the synapse had recovered before the second exposure"
    assert first is not None and second is not None
    assert second < first, f"re-habituation took {second} scans, the first habituation {first}"


def test_long_term_memory_numbers():
    """The numbers quoted in the module docstring and the report."""
    assert reexposure(WangHsuSynapse())[:2] == (16, 3)
    assert reexposure(WangHsuSynapse(method="exact"))[:2] == (16, 5)
    assert reexposure(StanleySynapse())[:2] == (4, 4)
    assert reexposure(StanleySynapse(method="exact"))[:2] == (5, 5)


def test_recovery_is_slower_after_long_term_habituation():
    """z is the memory: after habituation it stays low through the rest, and recovery slows."""
    bank = WangHsuSynapse(others="forget").initialize(2)
    for _ in range(40):
        bank.step(0, NONE)
    z_after = bank.recovery_[0]
    assert z_after < 0.8
    bank.step(1, NONE)
    assert bank.recovery_[0] == z_after, "without stimulus z keeps its value"
    fresh_rate = 1.05 * 0.9 / 14.3
    assert 1.05 * z_after / 14.3 < fresh_rate


# ----------------------------------------------------------- bounds, monotony
@st.composite
def euler_params(draw):
    alpha = draw(st.floats(0.05, 2.0))
    beta = draw(st.floats(0.0, 3.0))
    l = draw(st.floats(0.2, 2.0))  # noqa: E741
    gamma = draw(st.floats(0.0, 0.99)) / l
    z0 = draw(st.floats(0.01, 1.0)) * l
    fastest = alpha * l + beta
    tau_w = fastest * draw(st.floats(1.0, 4.0))
    tau_n = fastest * draw(st.floats(1.0, 8.0))
    return dict(alpha=alpha, beta=beta, gamma=gamma, l=l, z0=z0, tau_winner=tau_w, tau_neighbour=tau_n)


steps = st.lists(
    st.tuples(st.integers(0, 3), st.integers(0, 3), st.floats(0.0, 1.0), st.floats(0.0, 3.0)),
    min_size=1, max_size=40,
)


@settings(max_examples=60, deadline=None)
@given(params=euler_params(), seq=steps, method=st.sampled_from(["euler", "exact"]),
       others=st.sampled_from(["hold", "forget"]))
def test_efficacy_and_recovery_stay_in_bounds(params, seq, method, others):
    syn = WangHsuSynapse(method=method, others=others, **params).initialize(4)
    for winner, neighbour, s, dt in seq:
        neighbours = np.array([neighbour] if neighbour != winner else [], dtype=np.intp)
        syn.step(winner, neighbours, stimulus=s, dt=dt)
        assert np.all(syn.efficacy_ >= 0.0) and np.all(syn.efficacy_ <= 1.0 + 1e-12)
        assert np.all(syn.recovery_ > 0.0) and np.all(syn.recovery_ <= params["l"] * (1 + 1e-12))


@settings(max_examples=60, deadline=None)
@given(params=euler_params(), s=st.floats(0.05, 1.0), n=st.integers(1, 80),
       method=st.sampled_from(["euler", "exact"]))
def test_monotone_under_a_constant_stimulus(params, s, n, method):
    syn = WangHsuSynapse(method=method, **params).initialize(1)
    y, z = [1.0], [params["z0"]]
    for _ in range(n):
        syn.step(0, NONE, stimulus=s)
        y.append(syn.efficacy_[0])
        z.append(syn.recovery_[0])
    assert np.all(np.diff(y) <= 1e-12), "a constant stimulus never raises the efficacy"
    assert np.all(np.diff(z) <= 1e-15), "nor the speed of recovery"


# ------------------------------------------------------------------ the bank
def test_grow_and_shrink_carry_both_state_arrays():
    syn = WangHsuSynapse().initialize(4)
    for unit in range(4):
        for _ in range(unit * 3):
            syn.step(unit, NONE)
    y, z = syn.efficacy_.copy(), syn.recovery_.copy()
    syn.shrink(np.array([0, 2]))
    assert np.array_equal(syn.efficacy_, y[[1, 3]]) and np.array_equal(syn.recovery_, z[[1, 3]])
    syn.grow(2)
    assert np.array_equal(syn.efficacy_[2:], [1.0, 1.0]) and np.array_equal(syn.recovery_[2:], [0.9, 0.9])
    assert WangHsuSynapse._per_unit == ("efficacy_", "recovery_")


def test_state_check_refuses_a_bad_recovery():
    syn = WangHsuSynapse().initialize(2)
    arrays, values, children = syn._export_state()
    for bad in (np.array([0.5, 0.0]), np.array([0.5, 1.5]), np.array([0.5])):
        with pytest.raises(StateError):
            clone(syn)._import_state({**arrays, "recovery_": bad}, values, children)


def test_saved_filter_keeps_the_long_term_memory(tmp_path):
    X = np.random.default_rng(0).random((60, 4))
    det = novelty.make("habituating", clusterer="som", synapse="wang-hsu", n_rows=3, n_columns=3).fit(X)
    det.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    assert np.array_equal(back.synapse_.recovery_, det.synapse_.recovery_)
    assert np.array_equal(back.stream(X), det.stream(X))


# ---------------------------------------------------------------- parameters
@pytest.mark.parametrize("params, match", [
    (dict(z0=1.2), r"'z0' parameter of WangHsuSynapse must be <= l \(1.0\)"),
    (dict(tau_winner=3.0), r"'tau_winner' parameter of WangHsuSynapse must be >= 3.05"),
    (dict(tau_forget=1.0), r"'tau_forget' parameter of WangHsuSynapse must be >= 1.05"),
    (dict(gamma=1.0), r"'gamma' parameter of WangHsuSynapse must be < 1"),
    (dict(beta=-1.0), r"'beta' parameter of WangHsuSynapse must be a float in \[0, inf\)"),
    (dict(l=0), r"'l' parameter of WangHsuSynapse must be a float in \(0, inf\)"),
    (dict(method="rk4"), r"'method' parameter of WangHsuSynapse must be one of 'euler', 'exact'"),
])
def test_invalid_parameters_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        WangHsuSynapse(**params).initialize(1)


def test_fast_constants_are_allowed_with_the_exact_method():
    syn = WangHsuSynapse(method="exact", tau_winner=0.5, gamma=3.0).initialize(1)
    for _ in range(10):
        syn.step(0, NONE)
    assert 0 <= syn.efficacy_[0] < 0.05 and 0 < syn.recovery_[0] < 1e-3


# ------------------------------------------------------------- exact solution
P = WangHsuSynapse()


def _reference(y, z, s, tau, t):
    def rhs(_, v):
        return [(P.alpha * v[1] * (P.y0 - v[0]) - P.beta * v[0] * s) / tau, P.gamma * v[1] * (v[1] - P.l) * s]

    return solve_ivp(rhs, (0, t), [y, z], method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]


@pytest.mark.parametrize("s, t", [(1.0, 5.0), (1.0, 40.0), (0.5, 13.3), (0.3, 0.7)])
def test_exact_method_matches_a_fine_numerical_solution(s, t):
    syn = WangHsuSynapse(method="exact").initialize(1)
    syn.step(0, NONE, stimulus=s, dt=t)
    y, z = _reference(1.0, 0.9, s, 3.33, t)
    assert abs(syn.efficacy_[0] - y) < 5e-6
    assert abs(syn.recovery_[0] - z) < 1e-12, "z is exact (equations 3-4)"


def test_exact_recovery_variable_is_the_logistic_closed_form():
    syn = WangHsuSynapse(method="exact").initialize(1)
    syn.step(0, NONE, dt=12.5)
    # 1/z(t) = 1/l + (1/z0 - 1/l) exp(gamma l S t)
    assert syn.recovery_[0] == pytest.approx(1 / (1 + (1 / 0.9 - 1) * math.exp(0.05 * 12.5)), rel=1e-13)


def test_exact_rest_is_equation_5_in_one_step():
    syn = WangHsuSynapse(method="exact", others="forget", tau_forget=7.0).initialize(2)
    for _ in range(10):
        syn.step(0, NONE)
    y, z = syn.efficacy_[0], syn.recovery_[0]
    syn.step(1, NONE, dt=9.0)
    assert syn.efficacy_[0] == pytest.approx(1 + (y - 1) * math.exp(-1.05 * z * 9.0 / 7.0), rel=1e-14)
    assert syn.recovery_[0] == z


def test_exact_without_habituation_term_is_closed_form():
    """beta = 0: y relaxes with the exact integral of z, one step of any length."""
    syn = WangHsuSynapse(method="exact", beta=0.0).initialize(1)
    syn.efficacy_[0] = 0.2
    syn.step(0, NONE, dt=6.0)
    integral = 6.0 - math.log(0.9 + 0.1 * math.exp(0.05 * 6.0)) / 0.05  # l h - ln(r) / (gamma S)
    assert syn.efficacy_[0] == pytest.approx(1 + (0.2 - 1) * math.exp(-1.05 * integral / 3.33), rel=1e-13)


# ----------------------------------------------------------------- long gaps
def habituated(method: str, others: str = "forget") -> WangHsuSynapse:
    syn = WangHsuSynapse(method=method, others=others).initialize(3)
    for _ in range(6):
        syn.step(0, np.array([1]), 1.0, 1.0)
    return syn


@pytest.mark.parametrize("method, dt", [("euler", 5000.0), ("exact", 1500.0)])
def test_a_long_gap_ends_in_closed_form_as_the_loop_would(method, dt, monkeypatch):
    fast, slow = habituated(method), habituated(method)
    fast.step(0, np.array([1]), 1.0, dt)
    monkeypatch.setattr(wang_hsu, "_MAX_SUBSTEPS", 10**12)  # every sub-step iterated
    slow.step(0, np.array([1]), 1.0, dt)
    # once settled, the closed form is within 2**-53 y0 of the loop (module docstring)
    np.testing.assert_allclose(fast.efficacy_, slow.efficacy_, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(fast.recovery_, slow.recovery_, rtol=1e-12, atol=1e-15)
    assert fast.efficacy_[2] == pytest.approx(slow.efficacy_[2], rel=1e-15)  # forgetting at fixed z


@pytest.mark.parametrize("method", ["euler", "exact"])
@pytest.mark.parametrize("dt", [1e10, 1e19, 1e300])
def test_a_long_gap_finishes_with_a_state_a_model_file_may_hold(method, dt):
    syn = habituated(method)
    syn.step(0, np.array([1]), 1.0, dt)
    assert syn.efficacy_[0] < 1e-15  # held under the stimulus for dt: habituated to 0
    syn.step(2, NONE, 0.0, dt)
    assert np.all((syn.efficacy_ >= 0) & (syn.efficacy_ <= syn.y0))
    assert np.all((syn.recovery_ > 0) & (syn.recovery_ <= syn.l))
    syn._check_state()  # what loading a model file checks


@pytest.mark.parametrize("stimulus", [5e-324, 1e-300, 1e-20])
def test_a_vanishing_stimulus_leaves_the_exact_step_finite(stimulus):
    # gamma * S underflows to 0 for a subnormal S: the step must not divide by it.
    syn = WangHsuSynapse(method="exact").initialize(2)
    syn.step(0, np.array([1]), stimulus=1.0)
    before_y, before_z = syn.efficacy_.copy(), syn.recovery_.copy()
    syn.step(0, np.array([1]), stimulus=stimulus, dt=2.0)
    assert np.all(np.isfinite(syn.efficacy_)) and np.all(np.isfinite(syn.recovery_))
    # so weak a stimulus acts like none: the efficacy recovers towards y0, z holds
    assert np.all(syn.efficacy_ >= before_y) and np.all(syn.efficacy_ <= 1.0)
    assert syn.recovery_ == pytest.approx(before_z, rel=1e-15)
