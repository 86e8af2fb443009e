"""The Grow-When-Required network against steps computed by hand (Marsland et al. 2002), and its growth on a stream."""

import math

import numpy as np
import pytest
from sklearn.base import clone

import novelty
from novelty import datasets
from novelty._component import StateError
from novelty.clusterers.gwr import GrowWhenRequired
from novelty.habituation.stanley import StanleySynapse

ALPHA, TAU_B, TAU_N = 1.05, 3.33, 14.3


def exact_step(h, tau, stimulus=1.0):
    """One firing of Stanley's equation solved exactly (the paper's closed form, one step)."""
    h_inf = 1.0 - stimulus / ALPHA
    return h_inf + (h - h_inf) * math.exp(-ALPHA / tau)


def closed_form(t, tau):
    """The paper's h(t) = h0 - S/alpha (1 - exp(-alpha t / tau)) with h0 = S = 1."""
    return 1.0 - (1.0 - math.exp(-ALPHA * t / tau)) / ALPHA


def gwr_by_hand(weights, edges=(), counters=None, unit_ids=None, **params):
    """A network with the given units, edges ({(i, j): age}) and firing counters, via the model-file path."""
    weights = np.asarray(weights, dtype=np.float64)
    n = len(weights)
    ages = np.full((n, n), -1, dtype=np.int32)
    for (i, j), age in dict(edges).items():
        ages[i, j] = ages[j, i] = age
    ids = np.arange(n) if unit_ids is None else np.asarray(unit_ids)
    net = GrowWhenRequired(**params)
    net._validate_params()
    firing = net._new_firing_counters().initialize(n)
    if counters is not None:
        firing.efficacy_[:] = counters
    net._import_state(
        {"weights_": weights, "edge_ages_": ages, "unit_ids_": ids.astype(np.int64)},
        {"next_unit_id_": int(ids.max()) + 1,
         **({"activity_threshold_": 0.0} if net.activity_threshold == "auto" else {})},
        {"firing_": firing},
    )
    return net


def edge_dict(net):
    pairs, ages = net.edges()
    return {(int(i), int(j)): int(a) for (i, j), a in zip(pairs, ages)}


# ---------------------------------------------------------------- defaults
def test_defaults():
    net = GrowWhenRequired()
    assert (net.habituation_threshold, net.epsilon_b, net.epsilon_n, net.max_age) == (0.1, 0.1, 0.01, 50)
    assert net.activity_threshold == 0.85 and net.max_units is None
    net.initialize(np.random.default_rng(0).random((10, 3)), random_state=0)
    assert net.n_units_ == 2 and net.edges()[0].shape == (0, 2)
    assert isinstance(net.firing_, StanleySynapse)
    counter = net.firing_
    assert (counter.method, counter.tau_winner, counter.tau_neighbour, counter.alpha, counter.y0) == (
        "exact", TAU_B, TAU_N, ALPHA, 1.0)
    np.testing.assert_array_equal(counter.efficacy_, [1.0, 1.0])


def test_the_firing_counter_is_configurable():
    by_name = GrowWhenRequired(firing="stanley").initialize(np.zeros((2, 2)))
    assert isinstance(by_name.firing_, StanleySynapse) and by_name.firing_.method == "euler"
    mine = StanleySynapse(tau_winner=5.0, method="exact")
    net = GrowWhenRequired(firing=mine).initialize(np.zeros((2, 2)))
    assert net.firing_ is not mine and net.firing_.tau_winner == 5.0
    assert not hasattr(mine, "efficacy_"), "the parameter instance is cloned, never fitted"
    with pytest.raises(ValueError, match="'firing' parameter of GrowWhenRequired"):
        GrowWhenRequired(firing=3).initialize(np.zeros((2, 2)))


# ------------------------------------------------------------ steps by hand
def test_a_far_input_adds_a_unit_halfway_when_the_winner_has_fired_often():
    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0]], counters=[0.0625, 0.5], unit_ids=[4, 7])
    x = np.array([0.0, 1.0])
    m = net.match(x)
    assert (m.winner, m.runner_up, m.distance) == (0, 1, 1.0)
    assert m.neighbours.tolist() == [1]   # t learns with s once connected (step 5)
    growth = net.adapt(x, m)
    # step 6: a = exp(-1) < 0.85 and h_s = 0.0625 < 0.1, so step 7 adds r = (w_s + x) / 2
    assert growth.added == 1 and growth.removed.size == 0
    np.testing.assert_array_equal(net.weights_, [[0, 0], [1, 0], [0, 0.5]])   # s and t do not move
    assert edge_dict(net) == {(0, 2): 1, (1, 2): 0}     # s-t replaced by r-s (aged in step 9) and r-t
    np.testing.assert_array_equal(net.unit_ids_, [4, 7, 8])
    # step 10: s habituates with tau_b, its neighbour r (new, h = 1) with tau_n; t is no longer a neighbour
    np.testing.assert_allclose(net.firing_.efficacy_, [exact_step(0.0625, TAU_B), 0.5, exact_step(1.0, TAU_N)],
                               rtol=1e-15)


def test_a_far_input_adapts_while_the_winner_is_fresh():
    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0]], counters=[0.5, 0.75])
    x = np.array([0.0, 1.0])
    growth = net.adapt(x, net.match(x))
    assert growth.added == 0   # h_s = 0.5 >= h_T: the winner has not learned yet
    np.testing.assert_allclose(net.weights_, [[0.0, 0.1 * 0.5], [1.0 - 0.01 * 0.75, 0.01 * 0.75]], rtol=1e-15)


def test_a_near_input_moves_the_winner_by_eps_b_h_s_and_neighbours_by_eps_n_h_i():
    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [3.0, 3.0]],
                      edges={(0, 2): 5, (1, 3): 2}, counters=[0.5, 0.75, 0.25, 1.0])
    x = np.array([0.125, 0.0])
    m = net.match(x)
    assert (m.winner, m.runner_up, m.neighbours.tolist()) == (0, 1, [1, 2])
    growth = net.adapt(x, m)
    assert growth.added == 0 and growth.removed.size == 0   # a = exp(-1/8) = 0.88 >= a_T
    expected = np.array([
        [0.1 * 0.5 * 0.125, 0.0],                       # s: eps_b * h_s * (x - w_s)
        [1.0 + 0.01 * 0.75 * -0.875, 0.0],              # t, connected in step 5
        [0.01 * 0.25 * 0.125, 1.0 + 0.01 * 0.25 * -1.0],  # an old neighbour
        [3.0, 3.0],                                      # not a neighbour
    ])
    np.testing.assert_allclose(net.weights_, expected, rtol=1e-15)
    assert edge_dict(net) == {(0, 1): 1, (0, 2): 6, (1, 3): 2}
    np.testing.assert_allclose(
        net.firing_.efficacy_,
        [exact_step(0.5, TAU_B), exact_step(0.75, TAU_N), exact_step(0.25, TAU_N), 1.0], rtol=1e-15)


def test_firing_counters_follow_the_papers_closed_form():
    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0]])
    x = np.zeros(2)   # on unit 0: activity 1, nothing is ever added and nothing moves
    for t in range(1, 31):
        net.learn_one(x)
        assert net.firing_.efficacy_[0] == pytest.approx(closed_form(t, TAU_B), rel=1e-12)
        assert net.firing_.efficacy_[1] == pytest.approx(closed_form(t, TAU_N), rel=1e-12)
    assert net.n_units_ == 2


def test_the_counters_are_the_projects_synapse_not_a_copy(monkeypatch):
    """Changing StanleySynapse changes the GWR's counters: the network holds no equation of its own."""
    def flat(self, rows, stimulus, tau, dt):
        self.efficacy_[rows] = 0.25

    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0], [5.0, 5.0]], edges={(0, 1): 0})
    monkeypatch.setattr(StanleySynapse, "_advance", flat)
    net.learn_one(np.zeros(2))
    np.testing.assert_array_equal(net.firing_.efficacy_, [0.25, 0.25, 1.0])


def test_euler_counters_by_name_take_the_2000_papers_values():
    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0]], firing="stanley")
    for expected in (0.6997, 0.4941, 0.3533):   # Marsland et al. (2000), Table 1
        net.learn_one(np.zeros(2))
        assert round(float(net.firing_.efficacy_[0]), 4) == expected


def test_an_old_edge_and_the_unit_it_leaves_alone_are_removed_ids_stable():
    net = gwr_by_hand([[0, 0], [1, 1], [0.25, 0], [0.5, 0]], edges={(0, 1): 3, (0, 2): 0, (2, 3): 0},
                      counters=[0.5, 0.5, 0.5, 0.5], unit_ids=[10, 11, 12, 13], max_age=3)
    x = np.array([0.0625, 0.0])
    growth = net.adapt(x, net.match(x))
    assert growth.added == 0 and growth.removed.tolist() == [1]
    np.testing.assert_array_equal(net.unit_ids_, [10, 12, 13])
    assert edge_dict(net) == {(0, 1): 1, (1, 2): 0}
    assert net.firing_.n_units_ == 3
    # the removed unit was a neighbour when the counters habituated (step 10 comes before step 11)
    np.testing.assert_allclose(net.firing_.efficacy_, [exact_step(0.5, TAU_B), exact_step(0.5, TAU_N), 0.5])


def test_max_units_stops_growth():
    net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0]], counters=[0.0625, 0.0625], max_units=2)
    x = np.array([0.0, 1.0])
    growth = net.adapt(x, net.match(x))
    assert growth.added == 0 and net.n_units_ == 2
    assert net.weights_[0, 1] == pytest.approx(0.1 * 0.0625)   # adapts instead


# ---------------------------------------------------------------- validation
def test_parameter_messages():
    with pytest.raises(ValueError, match=r"The 'activity_threshold' parameter of GrowWhenRequired must be "
                                         r"a float in \[0, 1\] or one of 'auto'\. Got 1.5 instead\."):
        GrowWhenRequired(activity_threshold=1.5).initialize(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="'max_units'"):
        GrowWhenRequired(max_units=1).initialize(np.zeros((2, 2)))


def test_inconsistent_state_is_refused():
    net = gwr_by_hand([[0, 0], [1, 0], [0, 1]], edges={(0, 1): 0, (1, 2): 2})
    arrays, values, children = net._export_state()
    short = clone(children["firing_"]).initialize(2)
    with pytest.raises(StateError, match="firing_"):
        clone(net)._import_state(arrays, values, {"firing_": short})
    with pytest.raises(StateError, match="firing_"):
        clone(net)._import_state(arrays, values, {})
    bad = dict(arrays, edge_ages_=np.triu(arrays["edge_ages_"] + 1) - 1)
    with pytest.raises(StateError, match="symmetric"):
        clone(net)._import_state(bad, values, children)


# ---------------------------------------------- options for novelty (ours)
def test_without_the_firing_condition_a_far_input_gets_a_unit_at_once():
    gwr = GrowWhenRequired(firing_condition=False).initialize(np.zeros((1, 2)), random_state=0)
    match, growth = gwr.learn_one(np.array([1.0, 0.0]))
    assert growth.added == 1 and not growth.new_winner
    np.testing.assert_array_equal(gwr.weights_[-1], 0.5 * (gwr.weights_[match.winner] + [1.0, 0.0]))


def test_new_unit_wins_fires_its_counter_and_synapse():
    from novelty.filter import HabituatingFilter

    gwr = GrowWhenRequired(firing_condition=False, new_unit_wins=True, firing="stanley")
    det = HabituatingFilter(clusterer=gwr).fit(np.zeros((1, 2)))
    far = np.array([5.0, 5.0])
    assert det.score_one(far) == 1.0  # would get a unit of its own: a fresh synapse's novelty
    assert det.score_learn_one(far) == 1.0
    once = 1 + (1.0 / 3.33) * (1.05 * 0 - 1)  # one Euler step from y0 = 1 (tau 3.33, alpha 1.05)
    # the new unit's counter: a neighbour's step (step 10), then a winner's
    after_nb = 1 + (1.0 / 14.3) * (-1)
    assert det.synapse_.efficacy_[-1] == pytest.approx(once, abs=1e-15)
    assert det.clusterer_.firing_.efficacy_[-1] == pytest.approx(
        after_nb + (1.0 / 3.33) * (1.05 * (1 - after_nb) - 1), abs=1e-15)
    assert det.score_one(det.clusterer_.weights_[-1]) == det.synapse_.efficacy_[-1]  # matched by it
    assert det.score_one(far) == 1.0  # still far (the new unit is halfway): would get another


def test_auto_threshold_is_exp_of_minus_the_radius():
    X = np.array([[0.0, 0.0], [0.3, 0.0], [0.3, 0.4], [2.0, 0.4]])
    gwr = GrowWhenRequired(activity_threshold="auto").initialize(X, random_state=0)
    # nearest distinct distances 0.3, 0.3, 0.4, 1.7; the 0.9 quantile
    assert gwr.activity_threshold_ == np.exp(-np.quantile([0.3, 0.3, 0.4, 1.7], 0.9))
    gwr.calibrate(None)
    assert gwr.activity_threshold_ == 0.0  # no scale: no growth
    gwr.calibrate(0.5)
    assert gwr.activity_threshold_ == np.exp(-0.5)
    fixed = GrowWhenRequired(activity_threshold=0.7).initialize(X, random_state=0)
    fixed.calibrate(0.5)
    assert fixed.activity_threshold_ == 0.7 and not fixed.uses_match_scale


def test_auto_threshold_alone_calibrates_on_the_first_200_scans():
    # Rows after the 200th do not move a_T: on a grid of spacing 0.1 every
    # nearest distinct neighbour is 0.1 away, so a_T = exp(-0.1) whatever follows.
    grid = np.arange(200, dtype=np.float64)[:, None] * 0.1
    far = np.random.default_rng(0).uniform(100, 1e4, size=(5000, 1))
    gwr = GrowWhenRequired(activity_threshold="auto").initialize(np.vstack([grid, far]), random_state=0)
    assert gwr.activity_threshold_ == pytest.approx(math.exp(-0.1), rel=1e-12)


# ------------------------------------------------- growth on a stream
def test_gwr_grows_only_while_the_stream_shows_it_something_new(corridor, traversals):
    rng = np.random.default_rng(0)
    a, c = corridor(1), corridor(2)
    plan = traversals(a, 6, rng) + traversals(c, 4, rng) + traversals(a, 2, rng)
    net = GrowWhenRequired().initialize(plan[0], random_state=0)
    sizes = []
    for scans in plan:
        for x in scans:
            net.learn_one(x)
        sizes.append(net.n_units_)
    growth = np.diff([2] + sizes)
    # measured: sizes 22 43 47 49 51 51 | 71 91 93 95 | 95 96
    assert growth[0] + growth[1] >= 30, "the first traversals of a new corridor add units"
    assert growth[3:6].sum() <= 6, "repeated traversals level off"
    assert growth[6] >= 15, "a new corridor makes the network grow again"
    assert growth[9] <= 3, "and it levels off on the new corridor too"
    assert growth[10:].sum() <= 3, "the first corridor is still known after the second"


def test_gwr_filter_novelty_falls_on_repetition_and_rises_on_a_new_corridor(corridor, traversals):
    rng = np.random.default_rng(0)
    a, c = corridor(1), corridor(2)
    det = novelty.make("habituating", clusterer="gwr", synapse="stanley")
    means = [float(det.stream(scans).mean()) for scans in traversals(a, 5, rng) + traversals(c, 1, rng)]
    assert all(later < earlier for earlier, later in zip(means[:4], means[1:5]))
    assert means[5] > 3 * means[4]


def _paper_corridor(name, run):
    return datasets.load(name, run=run).X


def test_gwr_growth_on_the_papers_corridors_a_then_c():
    """On the simulated corridors GWR's growth dies down in A and picks up again in C.

    The activity threshold sets the insertion radius and depends on the data
    (Marsland et al. 2002 set it per experiment). With the default 0.85
    (radius 0.16) the simulated corridor A never levels off: about a quarter
    of the scans of a new run lie farther than 0.16 from every scan of earlier
    runs (door frames and corners flicker on the diagonal sensors), so A keeps
    adding 15-20 units a run. With 0.7 (radius 0.36) seed 0 gives
    21, 36, 48, 59, 70, 77, 86, 91 units after the runs of A, then 110 after C.
    """
    a = [_paper_corridor("paper-a", run) for run in range(8)]
    c = [_paper_corridor("paper-c", run) for run in range(1)]
    net = GrowWhenRequired(activity_threshold=0.7).initialize(a[0], random_state=0)
    sizes = []
    for scans in a + c:
        for x in scans:
            net.learn_one(x)
        sizes.append(net.n_units_)
    growth = np.diff([2] + sizes)
    early, late, new = growth[1:4].mean(), growth[5:8].mean(), growth[8]
    assert late <= 0.7 * early, f"growth dies down on corridor A: {sizes}"
    assert new >= 2 * late, f"and picks up again on corridor C: {sizes}"


def test_gwr_with_a_configured_counter_round_trips(tmp_path, corridor):
    X = corridor(1, n_scans=120)
    counter = StanleySynapse(tau_winner=2.0, method="exact", others="forget")
    det = novelty.make("habituating", clusterer="gwr", firing=counter).fit(X)
    det.save(tmp_path / "m.npz")
    back = novelty.load(tmp_path / "m.npz")
    assert back.clusterer.firing.tau_winner == 2.0 and back.clusterer_.firing_.others == "forget"
    np.testing.assert_array_equal(back.stream(X[::-1]), det.stream(X[::-1]))


def test_insertion_radius_is_a_multiple_of_the_calibrated_scale():
    gwr = GrowWhenRequired(activity_threshold="auto", insertion_radius=2.0)
    gwr.initialize(np.zeros((2, 2)), random_state=0)
    gwr.calibrate(0.25)
    assert gwr.activity_threshold_ == np.exp(-0.5)
    fixed = GrowWhenRequired(activity_threshold=0.7, insertion_radius=2.0).initialize(np.zeros((2, 2)))
    fixed.calibrate(0.25)
    assert fixed.activity_threshold_ == 0.7  # a given a_T is used as is


@pytest.mark.parametrize("radius,added", [(1.0, [1, 1]), (2.0, [0, 1])])
def test_a_scan_beyond_the_insertion_radius_gets_a_unit(radius, added):
    # sigma = 0.25: radius 1 inserts beyond 0.25, radius 2 beyond 0.5
    got = []
    for x in ([0.6, 0.0], [0.0, 0.6]):  # 0.4 from unit 1; 0.6 from unit 0
        net = gwr_by_hand([[0.0, 0.0], [1.0, 0.0]], activity_threshold="auto", insertion_radius=radius,
                          firing_condition=False)
        net.calibrate(0.25)
        match, growth = net.learn_one(np.array(x))
        got.append(growth.added)
        if growth.added:
            np.testing.assert_array_equal(net.weights_[-1], 0.5 * (net.weights_[match.winner] + x))
    assert got == added


def test_frozen_scoring_gives_a_scan_beyond_the_radius_the_fresh_units_novelty():
    from novelty.filter import HabituatingFilter

    gwr = GrowWhenRequired(activity_threshold="auto", insertion_radius=2.0, firing_condition=False,
                           new_unit_wins=True, epsilon_n=0.0)
    det = HabituatingFilter(clusterer=gwr, novelty_rule="product", match_scale=0.25)
    det.fit(np.array([[0.0, 0.0], [1.0, 0.0]]))  # the two units sit on the two scans
    np.testing.assert_array_equal(np.sort(det.clusterer_.weights_, axis=0), [[0.0, 0.0], [1.0, 0.0]])
    far, near = np.array([0.0, 0.6]), np.array([0.6, 0.0])  # 0.6 and 0.4 from their winners
    expected_far = 1.0 * (1 - np.exp(-0.36 / (2 * 0.0625)))  # a fresh synapse (y0 = 1)
    near_winner = det.clusterer_.match(near).winner
    expected_near = det.synapse_.efficacy_[near_winner] * (1 - np.exp(-0.16 / (2 * 0.0625)))
    assert expected_near < 0.7 < expected_far
    np.testing.assert_allclose(det.novelty(np.array([far, near])), [expected_far, expected_near],
                               rtol=0, atol=1e-15)
    assert det.score_learn_one(near) == pytest.approx(expected_near, abs=1e-15)
    assert det.clusterer_.n_units_ == 2  # within the radius: the winner adapts
    assert det.score_learn_one(far) == pytest.approx(expected_far, abs=1e-15)
    assert det.clusterer_.n_units_ == 3


def test_insertion_radius_must_be_positive():
    for value in (0, -1.0, "1.5", None):
        net = GrowWhenRequired(activity_threshold="auto", insertion_radius=value)
        with pytest.raises(ValueError, match=r"The 'insertion_radius' parameter of GrowWhenRequired must be "
                                             r"a float in \(0, inf\)\. Got .* instead\."):
            net.initialize(np.zeros((2, 2)))
        assert not hasattr(net, "weights_")
