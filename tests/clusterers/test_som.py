"""The Kohonen SOM against steps computed by hand (MiniSom style).

Units are row-major on the grid: unit r * n_columns + c sits at (r, c).
Hand values use dyadic fractions so that every expected weight is exact.
"""

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import novelty
import novelty.clusterers.base as clusterer_base
from novelty.clusterers.som import SOM


def som_with_weights(n_rows, n_columns, weights, **params):
    weights = np.asarray(weights, dtype=np.float64)
    som = SOM(n_rows=n_rows, n_columns=n_columns, **params).initialize(weights[:1], random_state=0)
    som.weights_[:] = weights
    return som


# ------------------------------------------------------------------ defaults
def test_defaults_are_the_papers():
    som = SOM()
    assert (som.n_rows, som.n_columns) == (10, 10)
    assert som.learning_rate == 0.25
    assert som.radius == 1
    assert som.decay == "constant"
    som.initialize(np.zeros((1, 3)), random_state=0)
    assert som.weights_.shape == (100, 3)
    assert som.current_learning_rate() == 0.25 and som.current_radius() == 1


# ---------------------------------------------------------- a step by hand
def test_one_step_on_a_2x2_map_by_hand():
    som = som_with_weights(2, 2, [[0, 0], [1, 0], [0, 1], [1, 1]])
    x = np.array([0.75, 0.25])
    m = som.match(x)
    # distances 0.625, 0.125, 1.125, 0.625
    assert m.winner == 1
    assert m.distance == 0.125
    assert sorted(m.neighbours.tolist()) == [0, 2, 3]  # radius 1 covers the whole 2 x 2 grid
    som.adapt(x, m)
    expected = [[0.1875, 0.0625], [0.9375, 0.0625], [0.1875, 0.8125], [0.9375, 0.8125]]
    np.testing.assert_array_equal(som.weights_, expected)
    assert som.n_updates_ == 1


def test_radius_zero_moves_only_the_winner():
    som = som_with_weights(2, 2, [[0, 0], [1, 0], [0, 1], [1, 1]], radius=0)
    x = np.array([0.75, 0.25])
    m = som.match(x)
    assert m.winner == 1 and m.neighbours.size == 0
    som.adapt(x, m)
    np.testing.assert_array_equal(som.weights_, [[0, 0], [0.9375, 0.0625], [0, 1], [1, 1]])


def test_3x3_map_centre_has_8_neighbours_corner_has_3():
    grid = [[r, c] for r in range(3) for c in range(3)]
    som = som_with_weights(3, 3, grid)
    centre = som.match(np.array([1.0, 1.0]))
    assert centre.winner == 4
    assert sorted(centre.neighbours.tolist()) == [0, 1, 2, 3, 5, 6, 7, 8]
    corner = som.match(np.array([2.0, 2.0]))
    assert corner.winner == 8
    assert sorted(corner.neighbours.tolist()) == [4, 5, 7]
    edge = som.match(np.array([0.0, 1.0]))
    assert edge.winner == 1
    assert sorted(edge.neighbours.tolist()) == [0, 2, 3, 4, 5]


def test_corner_step_on_a_3x3_map_moves_only_its_neighbourhood():
    grid = np.array([[r, c] for r in range(3) for c in range(3)], dtype=float)
    som = som_with_weights(3, 3, grid)
    x = np.array([2.5, 2.5])
    som.adapt(x, som.match(x))
    expected = grid.copy()
    expected[[4, 5, 7, 8]] += 0.25 * (x - grid[[4, 5, 7, 8]])
    np.testing.assert_array_equal(som.weights_, expected)
    np.testing.assert_array_equal(som.weights_[[0, 1, 2, 3, 6]], grid[[0, 1, 2, 3, 6]])


def test_neighbourhood_on_the_papers_10x10_map():
    som = SOM().initialize(np.zeros((1, 2)), random_state=0)
    table = [som.neighbours_of(unit, 1) for unit in range(100)]
    assert sorted(table[45].tolist()) == [34, 35, 36, 44, 46, 54, 55, 56]  # (4, 5)
    assert sorted(table[0].tolist()) == [1, 10, 11]
    assert sorted(table[5].tolist()) == [4, 6, 14, 15, 16]
    assert sorted(len(n) for n in table)[::33] == [3, 5, 8, 8]
    np.testing.assert_array_equal(som.grid_positions()[45], [4, 5])


def test_rectangular_grid_is_row_major():
    som = SOM(n_rows=2, n_columns=5).initialize(np.zeros((1, 1)), random_state=0)
    np.testing.assert_array_equal(som.grid_positions()[[0, 4, 5, 9]], [[0, 0], [0, 4], [1, 0], [1, 4]])
    assert som.neighbours_of(4, 1).tolist() == [3, 8, 9]


def test_distance_is_squared_euclidean():
    som = som_with_weights(1, 2, [[0, 0, 0], [10, 10, 10]])
    m = som.match(np.array([1.0, 2.0, 2.0]))
    assert m.winner == 0
    assert m.distance == 9.0  # not 3.0
    rows, dist = som.winners(np.array([[1.0, 2.0, 2.0], [10, 10, 13]]))
    np.testing.assert_array_equal(rows, [0, 1])
    np.testing.assert_allclose(dist, [9.0, 9.0], rtol=1e-12)


def test_exact_tie_goes_to_the_lowest_row():
    som = som_with_weights(1, 3, [[0.0], [2.0], [2.0]])
    assert som.match(np.array([1.0])).winner == 0
    assert som.match(np.array([2.0])).winner == 1
    np.testing.assert_array_equal(som.winners(np.array([[1.0], [2.0]]))[0], [0, 1])


# ------------------------------------------------------------------ decay
@pytest.mark.parametrize(
    "decay, expected_lr, expected_radius",
    [
        # p(t) = p0 + (pf - p0) min(t/T, 1)
        ("linear", [0.5, 0.3, 0.1, 0.1], [3, 2, 0, 0]),
        # p(t) = pf + (p0 - pf) / (1 + 2t/T)
        ("asymptotic", [0.5, 0.3, 0.1 + 0.4 / 3, 0.1 + 0.4 / 5], [3, 2, 1, 1]),
        ("constant", [0.5, 0.5, 0.5, 0.5], [3, 3, 3, 3]),
    ],
)
def test_decay_schedules_at_0_half_and_full(decay, expected_lr, expected_radius):
    som = SOM(decay=decay, decay_steps=100, learning_rate=0.5, learning_rate_final=0.1,
              radius=3, radius_final=0.0).initialize(np.zeros((1, 1)), random_state=0)
    lrs, radii = [], []
    for t in (0, 50, 100, 200):
        som.n_updates_ = t
        lrs.append(som.current_learning_rate())
        radii.append(som.current_radius())
    np.testing.assert_allclose(lrs, expected_lr, rtol=1e-14)
    # radius 1.5 at T/2 rounds half up to 2; asymptotic at 2T: 3/5 -> 1
    assert radii == expected_radius


def test_decay_uses_the_scheduled_rate_and_shrinks_the_neighbourhood():
    som = SOM(n_rows=9, n_columns=9, decay="linear", decay_steps=4, learning_rate=0.5,
              learning_rate_final=0.1, radius=3, radius_final=0.0)
    som.initialize(np.zeros((1, 2)), random_state=0)
    grid = np.array([[r, c] for r in range(9) for c in range(9)], dtype=float)
    som.weights_[:] = grid
    x = np.array([4.0, 4.0])  # the centre unit 40 always wins
    sizes, rates = [], []
    for _ in range(5):
        rates.append(som.current_learning_rate())
        before = som.weights_.copy()
        m = som.match(x)
        assert m.winner == 40
        sizes.append(len(m.neighbours))
        som.adapt(x, m)
        moved = np.flatnonzero(np.any(som.weights_ != before, axis=1))
        assert sorted(moved.tolist()) == sorted(m.neighbours.tolist())  # the winner sits on x
    # radius 3, 2.25 -> 2, 1.5 -> 2, 0.75 -> 1, 0: (2r + 1)^2 - 1 neighbours
    assert sizes == [48, 24, 24, 8, 0]
    np.testing.assert_allclose(rates, [0.5, 0.4, 0.3, 0.2, 0.1], rtol=1e-14)


def test_learning_rate_one_copies_the_input():
    som = som_with_weights(1, 1, [[0.3, 0.7]], learning_rate=1.0)
    x = np.array([0.9, 0.1])
    som.adapt(x, som.match(x))
    np.testing.assert_allclose(som.weights_[0], x, rtol=0, atol=1e-15)  # w + (x - w), rounded


# ---------------------------------------------------------- quantisation error
def test_quantization_error_by_hand():
    som = som_with_weights(1, 2, [[0, 0], [3, 4]])
    X = np.array([[0.0, 1.0], [3.0, 0.0], [6.0, 8.0]])
    # nearest distances 1 (to (0,0)), 3 (to (0,0)), 5 (to (3,4))
    assert som.quantization_error(X) == pytest.approx(3.0, rel=1e-12)


# ------------------------------------------------------------ initialisation
def test_seeded_init_is_reproducible_and_in_range():
    X = np.zeros((5, 4))
    a = SOM(n_rows=3, n_columns=4).initialize(X, random_state=7)
    b = SOM(n_rows=3, n_columns=4).initialize(X, random_state=7)
    c = SOM(n_rows=3, n_columns=4).initialize(X, random_state=8)
    np.testing.assert_array_equal(a.weights_, b.weights_)
    assert not np.array_equal(a.weights_, c.weights_)
    assert a.weights_.shape == (12, 4)
    assert a.weights_.min() >= 0.0 and a.weights_.max() < 1.0
    d = SOM(n_rows=3, n_columns=4, init_range=(-2.0, -1.0)).initialize(X, random_state=7)
    assert d.weights_.min() >= -2.0 and d.weights_.max() < -1.0
    np.testing.assert_array_equal(a.unit_ids_, np.arange(12))
    assert a.next_unit_id_ == 12 and a.n_updates_ == 0


def test_sample_init_copies_rows_of_the_first_batch():
    X = np.arange(30, dtype=float).reshape(10, 3)
    som = SOM(n_rows=2, n_columns=3, init="sample").initialize(X, random_state=1)
    rows = {tuple(r) for r in X}
    assert all(tuple(w) in rows for w in som.weights_)
    som.weights_[0, 0] = -1.0
    assert X.min() == 0.0  # a copy, not a view of the user's data


# --------------------------------------------------- batch winners == match
def assert_winners_equal_match(som, X):
    rows, dist = som.winners(X)
    for i, x in enumerate(X):
        m = som.match(x)
        assert rows[i] == m.winner, f"row {i}"
        assert dist[i] == pytest.approx(m.distance, rel=1e-9, abs=1e-9 * (1 + x @ x))


def test_winners_equal_match_on_random_data():
    rng = np.random.default_rng(0)
    som = SOM(n_rows=6, n_columns=7).initialize(np.zeros((1, 5)), random_state=0)
    assert_winners_equal_match(som, rng.uniform(size=(500, 5)))


def near_tie_case(seed=1):
    rng = np.random.default_rng(seed)
    som = SOM(n_rows=1, n_columns=4).initialize(np.zeros((1, 6)), random_state=0)
    offset = 1e4  # large coordinates make |x|^2 - 2 x.w + |w|^2 lose the difference
    W = offset + rng.uniform(size=(4, 6))
    W[2:] += 5.0  # two well separated pairs: each midpoint is a tie of its pair only
    som.weights_[:] = W
    X = []
    for eps in [0.0, 1e-15, -1e-15, 1e-13, -1e-13, 1e-11, -1e-11, 1e-9, -1e-9]:
        for a, b in [(0, 1), (2, 3), (1, 0)]:
            X.append((W[a] + W[b]) / 2 + eps * (W[b] - W[a]))
    return som, np.array(X)


def test_winners_equal_match_on_constructed_near_ties():
    som, X = near_tie_case()
    assert_winners_equal_match(som, X)
    # the direct distances really are near-ties for these inputs
    d = ((som.weights_[None, :, :] - X[:, None, :]) ** 2).sum(axis=2)
    part = np.sort(d, axis=1)
    assert np.all(part[:, 1] - part[:, 0] < 1e-6 * part[:, 0])


def test_winners_equal_match_across_chunks(monkeypatch):
    monkeypatch.setattr(clusterer_base, "_CHUNK_ROWS", 5)
    som, ties = near_tie_case(seed=2)
    rng = np.random.default_rng(3)
    X = np.concatenate([ties, som.weights_[rng.integers(0, 4, 20)] + rng.normal(0, 0.3, (20, 6))])
    X = X[rng.permutation(len(X))]  # near-ties land in every block at various offsets
    assert_winners_equal_match(som, X)


def test_winners_on_a_single_unit_map():
    som = som_with_weights(1, 1, [[0.5, 0.5]])
    rows, dist = som.winners(np.array([[0.0, 0.0], [1.0, 1.0]]))
    np.testing.assert_array_equal(rows, [0, 0])
    np.testing.assert_allclose(dist, [0.5, 0.5])


# ---------------------------------------------------------------- validation
@pytest.mark.parametrize(
    "params, match",
    [
        ({"n_rows": 0}, r"The 'n_rows' parameter of SOM must be an int in \[1, inf\)\. Got 0 instead\."),
        ({"n_columns": 2.5}, r"'n_columns' parameter of SOM must be an int"),
        ({"learning_rate": 1.5}, r"'learning_rate' parameter of SOM must be a float in \[0, 1\]\. Got 1\.5"),
        ({"radius": -1}, r"'radius' parameter of SOM must be a float in \[0, inf\)"),
        ({"decay": "exponential"}, r"'decay' parameter of SOM must be one of 'constant', 'linear', 'asymptotic'"),
        ({"decay_steps": 0}, r"'decay_steps' parameter"),
        ({"init": "pca"}, r"'init' parameter of SOM must be one of 'uniform', 'sample'"),
        ({"init_range": (1.0, 0.0)}, r"'init_range' parameter of SOM must be a pair"),
        ({"init_range": (0.0, float("inf"))}, r"'init_range' parameter"),
    ],
)
def test_invalid_parameters_are_named_with_their_range(params, match):
    with pytest.raises(ValueError, match=match):
        SOM(**params).initialize(np.zeros((1, 2)), random_state=0)


# ---------------------------------------------------------------- properties
@st.composite
def som_and_input(draw):
    n_rows, n_cols = draw(st.integers(1, 4)), draw(st.integers(1, 4))
    n_features = draw(st.integers(1, 5))
    elements = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
    W = draw(hnp.arrays(np.float64, (n_rows * n_cols, n_features), elements=elements))
    x = draw(hnp.arrays(np.float64, (n_features,), elements=elements))
    lr = draw(st.floats(0.0, 1.0))
    radius = draw(st.integers(0, 2))
    return som_with_weights(n_rows, n_cols, W, learning_rate=lr, radius=radius), x


@settings(max_examples=80, deadline=None)
@given(som_and_input())
def test_winner_is_the_argmin_of_the_distance(case):
    som, x = case
    m = som.match(x)
    d = np.array([sum((wi - xi) ** 2 for wi, xi in zip(w, x)) for w in som.weights_])
    assert m.distance == pytest.approx(d.min(), rel=1e-12, abs=1e-12)
    assert d[m.winner] <= d.min() * (1 + 1e-12) + 1e-12
    assert m.winner not in m.neighbours.tolist()
    rows, _ = som.winners(x[None, :])
    assert rows[0] == m.winner


@settings(max_examples=80, deadline=None)
@given(som_and_input())
def test_an_update_moves_the_winner_and_neighbours_closer(case):
    som, x = case
    before = som.weights_.copy()
    m = som.match(x)
    som.adapt(x, m)
    lr = som.learning_rate
    moved = np.append(m.neighbours, m.winner)
    d_before = ((before[moved] - x) ** 2).sum(axis=1)
    d_after = ((som.weights_[moved] - x) ** 2).sum(axis=1)
    # w' - x = (1 - eta)(w - x): the distance shrinks by (1 - eta)^2, up to rounding
    assert np.all(d_after <= d_before * (1 - lr) ** 2 * (1 + 1e-9) + 1e-20 + 1e-12 * (x @ x))
    assert np.all(d_after <= d_before)
    others = np.setdiff1d(np.arange(som.n_units_), moved)
    np.testing.assert_array_equal(som.weights_[others], before[others])


# ------------------------------------------- a neighbour rate of its own (ours)
def test_neighbour_learning_rate_by_hand():
    """Not in the paper: the winner moves by eta = 0.25, its neighbours by their own 0.5."""
    som = som_with_weights(2, 2, [[0, 0], [1, 0], [0, 1], [1, 1]], neighbour_learning_rate=0.5)
    x = np.array([0.75, 0.25])
    som.adapt(x, som.match(x))
    expected = [[0.375, 0.125], [0.9375, 0.0625], [0.375, 0.625], [0.875, 0.625]]
    np.testing.assert_array_equal(som.weights_, expected)


def test_neighbour_learning_rate_none_is_the_papers_shared_rate():
    assert SOM().neighbour_learning_rate is None
    rng = np.random.default_rng(3)
    X = rng.random((200, 4))
    shared = SOM(n_rows=4, n_columns=4).initialize(X, random_state=0)
    same = SOM(n_rows=4, n_columns=4, neighbour_learning_rate=0.25).initialize(X, random_state=0)
    for x in X:
        shared.adapt(x, shared.match(x))
        same.adapt(x, same.match(x))
    np.testing.assert_array_equal(shared.weights_, same.weights_)


def test_neighbour_learning_rate_out_of_range_is_refused():
    with pytest.raises(ValueError, match="neighbour_learning_rate"):
        SOM(neighbour_learning_rate=1.5).initialize(np.zeros((1, 2)), random_state=0)


def test_neighbourhoods_are_the_chebyshev_balls_of_the_grid():
    som = SOM(n_rows=4, n_columns=7).initialize(np.zeros((1, 1)), random_state=0)
    pos = som.grid_positions()
    for radius in range(0, 5):
        for unit in range(28):
            cheb = np.abs(pos - pos[unit]).max(axis=1)
            expected = np.flatnonzero((cheb <= radius) & (np.arange(28) != unit))
            np.testing.assert_array_equal(som.neighbours_of(unit, radius), expected)


def test_a_large_map_needs_memory_in_proportion_to_its_units():
    tracemalloc.start()
    try:
        som = SOM(n_rows=60, n_columns=60).initialize(np.zeros((1, 2)), random_state=0)
        som.learn_one(np.array([0.5, 0.5]))
        som._rebuild_scratch()  # what loading a model file runs
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2_000_000  # 3600 units x 2 features are 58 kB; a unit-by-unit table 100 MB


def test_a_map_beyond_memory_is_a_value_error_that_says_so():
    with pytest.raises(ValueError, match=r"SOM with these parameters does not fit in memory .* Use fewer units"):
        novelty.make("hsom", n_rows=10**12).fit(np.zeros((3, 3)))
