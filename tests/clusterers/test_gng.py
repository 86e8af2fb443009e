"""Growing Neural Gas against steps computed by hand (Fritzke 1995, steps 2-9)."""

import numpy as np
import pytest

import novelty
from novelty._component import StateError
from novelty.clusterers.gng import GrowingNeuralGas

BETA = 0.0005  # the default error decay


def gng_by_hand(weights, edges=(), errors=None, unit_ids=None, n_inputs=0, **params):
    """A network with the given units and edges ({(i, j): age}), through the model-file path."""
    weights = np.asarray(weights, dtype=np.float64)
    n = len(weights)
    ages = np.full((n, n), -1, dtype=np.int32)
    for (i, j), age in dict(edges).items():
        ages[i, j] = ages[j, i] = age
    ids = np.arange(n) if unit_ids is None else np.asarray(unit_ids)
    net = GrowingNeuralGas(**params)
    net._validate_params()
    net._import_state(
        {"weights_": weights, "errors_": np.zeros(n) if errors is None else np.asarray(errors, float),
         "edge_ages_": ages, "unit_ids_": ids.astype(np.int64)},
        {"next_unit_id_": int(ids.max()) + 1, "n_inputs_": n_inputs},
        {},
    )
    return net


def edge_dict(net):
    pairs, ages = net.edges()
    return {(int(i), int(j)): int(a) for (i, j), a in zip(pairs, ages)}


# ---------------------------------------------------------------- defaults
def test_defaults_are_fritzkes():
    net = GrowingNeuralGas()
    assert (net.epsilon_b, net.epsilon_n, net.insertion_interval) == (0.2, 0.006, 100)
    assert (net.insertion_error_decay, net.error_decay, net.max_age) == (0.5, 0.0005, 50)
    net.initialize(np.random.default_rng(0).random((10, 3)), random_state=0)
    assert net.n_units_ == 2 and net.edges()[0].shape == (0, 2)   # two units, no edges
    np.testing.assert_array_equal(net.errors_, [0.0, 0.0])


def test_sample_init_takes_two_distinct_rows_of_the_first_batch():
    X = np.arange(20.0).reshape(10, 2)
    net = GrowingNeuralGas().initialize(X, random_state=3)
    rows = [int(np.flatnonzero((X == w).all(axis=1))[0]) for w in net.weights_]
    assert rows[0] != rows[1]
    again = GrowingNeuralGas().initialize(X, random_state=3)
    np.testing.assert_array_equal(again.weights_, net.weights_)
    uniform = GrowingNeuralGas(init="uniform", init_range=(2.0, 3.0)).initialize(X, random_state=0)
    assert np.all((uniform.weights_ >= 2.0) & (uniform.weights_ < 3.0))


# ------------------------------------------------------------ steps by hand
def test_first_two_inputs_by_hand():
    net = gng_by_hand([[0.0, 0.0], [1.0, 0.0]])
    x = np.array([0.25, 0.5])
    m = net.match(x)
    # squared distances 0.3125 and 0.8125; no edges yet, so no neighbours
    assert (m.winner, m.runner_up, m.distance) == (0, 1, 0.3125)
    assert m.neighbours.size == 0
    growth = net.adapt(x, m)
    assert growth.added == 0 and growth.removed.size == 0
    np.testing.assert_array_equal(net.weights_, [[0.05, 0.1], [1.0, 0.0]])   # eps_b = 0.2; w1 not a neighbour
    assert edge_dict(net) == {(0, 1): 0}                                       # step 6: a new edge, age 0
    np.testing.assert_allclose(net.errors_, [0.3125 * (1 - BETA), 0.0], rtol=1e-15)

    x = np.array([0.875, 0.125])
    m = net.match(x)
    assert (m.winner, m.runner_up) == (1, 0)
    assert m.neighbours.tolist() == [0]
    net.adapt(x, m)
    np.testing.assert_allclose(net.weights_[1], [1.0 + 0.2 * -0.125, 0.2 * 0.125], rtol=1e-15)
    np.testing.assert_allclose(net.weights_[0], [0.05 + 0.006 * 0.825, 0.1 + 0.006 * 0.025], rtol=1e-14)
    assert edge_dict(net) == {(0, 1): 0}          # aged to 1 in step 3, reset in step 6
    np.testing.assert_allclose(
        net.errors_, [0.3125 * (1 - BETA) ** 2, 2 * 0.125**2 * (1 - BETA)], rtol=1e-14)
    assert net.n_inputs_ == 2


def test_only_the_winners_edges_age():
    net = gng_by_hand([[0, 0], [1, 0], [0, 1], [5, 5]], edges={(0, 1): 3, (0, 2): 7, (2, 3): 4})
    x = np.array([0.0, 0.125])
    net.learn_one(x)   # winner 0, runner-up 2
    assert edge_dict(net) == {(0, 1): 4, (0, 2): 0, (2, 3): 4}


def test_insertion_between_the_units_of_largest_error():
    net = gng_by_hand([[0, 0], [1, 0], [0, 1]], edges={(0, 1): 0, (0, 2): 0},
                      errors=[1.0, 0.5, 0.2], insertion_interval=1)
    x = np.array([0.0, 0.875])
    m = net.match(x)
    assert (m.winner, m.runner_up, m.neighbours.tolist()) == (2, 0, [0])
    growth = net.adapt(x, m)
    assert growth.added == 1 and growth.removed.size == 0
    # steps 4-5: E_2 = 0.2 + 0.125^2, w_2 = (0, 0.975), w_0 = (0, 0.006 * 0.875)
    # step 8: q = 0 (E = 1), f = 1 (its neighbour of larger error 0.5 > 0.215625)
    w0 = np.array([0.0, 0.006 * 0.875])
    np.testing.assert_allclose(net.weights_[3], (w0 + [1.0, 0.0]) / 2, rtol=1e-15)
    expected_errors = np.array([0.5, 0.25, 0.2 + 0.125**2, 0.5]) * (1 - BETA)   # E_r = alpha * E_q
    np.testing.assert_allclose(net.errors_, expected_errors, rtol=1e-15)
    assert edge_dict(net) == {(0, 2): 0, (0, 3): 0, (1, 3): 0}   # q-f replaced by q-r and r-f
    np.testing.assert_array_equal(net.unit_ids_, [0, 1, 2, 3])
    assert net.next_unit_id_ == 4


def test_insertion_every_lambda_inputs_until_max_units():
    X = np.random.default_rng(0).random((700, 2))
    net = GrowingNeuralGas(insertion_interval=100, max_units=6, max_age=10_000)
    net.initialize(X, random_state=0)
    sizes = []
    for x in X:
        net.learn_one(x)
        sizes.append(net.n_units_)
    # no edge ever gets old enough to go, so only insertions change the size
    assert sizes[98] == 2 and sizes[99] == 3 and sizes[199] == 4 and sizes[399] == 6
    assert sizes[-1] == 6


def test_an_old_edge_and_the_unit_it_leaves_alone_are_removed_ids_stable():
    net = gng_by_hand([[0, 0], [1, 1], [0.25, 0], [0.5, 0]],
                      edges={(0, 1): 3, (0, 2): 0, (2, 3): 0}, unit_ids=[10, 11, 12, 13], max_age=3)
    x = np.array([0.0625, 0.0])
    m = net.match(x)
    assert (m.winner, m.runner_up) == (0, 2)
    growth = net.adapt(x, m)
    # step 3 ages 0-1 to 4 > max_age: the edge goes, and unit 1 (id 11) with it
    assert growth.added == 0 and growth.removed.tolist() == [1]
    np.testing.assert_array_equal(net.unit_ids_, [10, 12, 13])
    assert net.next_unit_id_ == 14
    assert edge_dict(net) == {(0, 1): 0, (1, 2): 0}            # rows renumbered, edges follow
    # the old unit 2 learned as a neighbour (eps_n); the old unit 3 did not move
    np.testing.assert_allclose(net.weights_[1:], [[0.25 - 0.006 * 0.1875, 0], [0.5, 0]], rtol=1e-15)
    assert net.errors_.shape == (3,) and net.edge_ages_.shape == (3, 3)


def test_edge_of_age_max_age_survives():
    net = gng_by_hand([[0, 0], [1, 1], [0.25, 0]], edges={(0, 1): 2, (0, 2): 0}, max_age=3)
    net.learn_one(np.array([0.0, 0.0]))
    assert edge_dict(net) == {(0, 1): 3, (0, 2): 0}


# ---------------------------------------------------------------- validation
def test_parameter_messages():
    with pytest.raises(ValueError, match=r"The 'max_age' parameter of GrowingNeuralGas must be an int "
                                         r"in \[1, 2\*\*53\]\. Got 0 instead\."):
        GrowingNeuralGas(max_age=0).initialize(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="'insertion_interval'"):
        GrowingNeuralGas(insertion_interval=0.5).initialize(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="'init_range'"):
        GrowingNeuralGas(init_range=(1.0, 0.0)).initialize(np.zeros((2, 2)))


@pytest.mark.parametrize("corrupt, message", [
    (lambda a: a["edge_ages_"].__setitem__((0, 1), 5), "symmetric"),
    (lambda a: a["edge_ages_"].__setitem__((1, 1), 0), "diagonal"),
    (lambda a: a.__setitem__("edge_ages_", a["edge_ages_"][:2, :2]), "shape"),
    (lambda a: a.__setitem__("errors_", -a["errors_"] - 1), "negative"),
    (lambda a: a.__setitem__("weights_", a["weights_"][:1]), "shape|units"),
])
def test_inconsistent_state_is_refused(corrupt, message):
    net = gng_by_hand([[0, 0], [1, 0], [0, 1]], edges={(0, 1): 0, (1, 2): 2}, errors=[0.1, 0.2, 0.3])
    arrays, values, _ = net._export_state()
    arrays = {k: np.array(v) for k, v in arrays.items()}
    corrupt(arrays)
    with pytest.raises(StateError, match=message):
        GrowingNeuralGas()._import_state(arrays, values, {})


def test_a_match_without_runner_up_is_completed():
    from novelty.clusterers.base import Match

    a = gng_by_hand([[0, 0], [1, 0], [0, 1]], edges={(0, 1): 0})
    b = gng_by_hand([[0, 0], [1, 0], [0, 1]], edges={(0, 1): 0})
    x = np.array([0.0, 0.75])
    m = a.match(x)
    a.adapt(x, m)
    b.adapt(x, Match(m.winner, m.distance, m.neighbours))
    np.testing.assert_array_equal(a.edge_ages_, b.edge_ages_)
    assert edge_dict(b) == {(0, 1): 0, (0, 2): 0}   # winner 2, runner-up 0


def test_an_age_or_interval_beyond_any_run_is_a_value_error():
    # 2**63 - 1 rounds to 2**63 in the compiled steps' float parameters and wraps round
    X = np.random.default_rng(0).uniform(size=(30, 3))
    for name in ("max_age", "insertion_interval", "max_units"):
        with pytest.raises(ValueError, match=rf"'{name}' parameter of GrowingNeuralGas must be an int in"):
            novelty.make("gng-stanley", **{f"clusterer__{name}": 2**63 - 1}).fit(X)
    novelty.make("gng-stanley", clusterer__max_age=2**53).fit(X)  # never reached, as 2**63 - 1 meant
