"""The occupancy grid against cells computed by hand on a small corridor, and against a grid of dictionaries.

Cells of 1 m; the robot stands at (0.5, 0.5) facing along a corridor (x),
its two sectors seeing the walls at y = 3.5 (cell row 3) and y = -2.5 (row
-3). With l_occ = 1 and l_free = -0.5 (dyadic: every sum exact) a cell's
log-odds after k echoes and f passes is k - f / 2, clamped.
"""

import math

import numpy as np
import pytest

from novelty.baselines.occupancy_grid import OccupancyGrid
from novelty.maps.grid_walk import walk_cells
from novelty.io.scans.points import example_rows
from novelty.maps.scan_rays import MapRangeWarning, scan_rays
from novelty.maps.tiles import GridFullWarning

EXACT = {"cell_size": 1.0, "l_occ": 1.0, "l_free": -0.5, "l_min": -2.0, "l_max": 2.0, "tolerance": 0}


def row(*echoes, robot=(0.5, 0.5)):
    """One points row: a sector for each echo (x, y) (the ring's threshold 8 m); None: a sector with no echo, free
    4 m to the robot's left."""
    near, xs, ys = [], [], []
    for echo in echoes:
        if echo is None:
            near.append(0.0)
            echo = (robot[0], robot[1] + 4.0)
        else:
            near.append(max(0.0, 1.0 - math.hypot(echo[0] - robot[0], echo[1] - robot[1]) / 8.0))
        xs.append(echo[0])
        ys.append(echo[1])
    return [*robot, 0.0, *near, *xs, *ys]


CORRIDOR = row((0.5, 3.5), (0.5, -2.5))


# ------------------------------------------------------------------ equations (1) and (2), by hand
def test_a_corridor_seen_k_times_holds_its_walls_occupied_and_the_floor_free():
    for k in (1, 2, 3, 5):
        grid = OccupancyGrid(**EXACT).fit([CORRIDOR] * k)
        cells = [[0, 3], [0, 2], [0, 1], [0, 0], [0, -1], [0, -2], [0, -3], [0, 4], [1, 0]]
        clamp = lambda v: min(2.0, max(-2.0, v))  # noqa: E731
        expected = [clamp(k), clamp(-k / 2), clamp(-k / 2), clamp(-k / 2), clamp(-k / 2), clamp(-k / 2), clamp(k),
                    0.0, 0.0]
        assert grid.log_odds(cells).tolist() == expected
        assert grid.scans_ == k and grid.n_tiles_ == 2          # tiles (0, 0) and (0, -1): rows -16..-1


def test_a_cell_is_updated_once_a_scan_and_an_echo_wins_over_a_pass():
    # two beams through (0, 1): one pass; a third beam's echo in (0, 2), which the second passes through
    grid = OccupancyGrid(**EXACT).fit([row((0.5, 3.5), (0.5, 2.5), (0.4, 3.5))])
    assert grid.log_odds([[0, 1], [0, 2], [0, 3]]).tolist() == [-0.5, 1.0, 1.0]


def test_a_beam_without_echo_frees_its_whole_length():
    grid = OccupancyGrid(**EXACT).fit([row(None)])
    assert grid.log_odds([[0, k] for k in range(6)]).tolist() == [-0.5] * 5 + [0.0]


# ------------------------------------------------------------------ equation (3)
def test_an_echo_in_free_cells_contradicts_the_grid_by_its_share_of_the_echoes():
    grid = OccupancyGrid(**{**EXACT, "free_below": -1.0}).fit([CORRIDOR] * 3)   # the floor at -1.5
    scans = [CORRIDOR, row((0.5, 1.5), (0.5, -2.5)), row((0.5, 1.5), (0.5, -1.5)), row((0.5, 1.5), None)]
    assert grid.novelty(scans).tolist() == [0.0, 0.5, 1.0, 1.0]
    # one pass is not enough at -1, is at -0.25
    once = OccupancyGrid(**{**EXACT, "free_below": -1.0}).fit([CORRIDOR])
    assert once.novelty([row((0.5, 1.5), (0.5, -2.5))]).tolist() == [0.0]
    once.set_params(free_below=-0.25)
    assert once.novelty([row((0.5, 1.5), (0.5, -2.5))]).tolist() == [0.5]


def test_tolerance_asks_the_cells_around_an_echo_to_be_free_too():
    grid = OccupancyGrid(**{**EXACT, "free_below": -1.0, "tolerance": 1}).fit([CORRIDOR] * 3)
    # (0, 2) lies beside the wall (0, 3): not evidence; (0, 1) has free cells all round only along x = 0:
    # its neighbours (1, 0..2) and (-1, 0..2) are unknown
    assert grid.novelty([row((0.5, 2.5), (0.5, -2.5)), row((0.5, 1.5), (0.5, -2.5))]).tolist() == [0.0, 0.0]
    wide = [row((x, 3.5), (x, -2.5), robot=(x, 0.5)) for x in (-0.5, 0.5, 1.5)] * 3
    grid = OccupancyGrid(**{**EXACT, "free_below": -1.0, "tolerance": 1}).fit(wide)
    assert grid.novelty([row((0.5, 1.5), (0.5, -2.5))]).tolist() == [0.5]


def test_a_beam_through_occupied_cells_contradicts_the_grid():
    # the wall at row 3 learned; then the robot sees through it to (0.5, 5.5): the beam passes (0, 3)
    grid = OccupancyGrid(**{**EXACT, "evidence": "occupied"}).fit([CORRIDOR] * 2)
    through = row((0.5, 5.5), (0.5, -2.5))
    assert grid.novelty([CORRIDOR, through]).tolist() == [0.0, 0.5]
    # the echo's own cell and those within tolerance are left out: an echo one cell past the wall is it
    near = OccupancyGrid(**{**EXACT, "evidence": "occupied", "tolerance": 1}).fit([CORRIDOR] * 2)
    assert near.novelty([row((0.5, 4.5), (0.5, -2.5)), through]).tolist() == [0.0, 0.5]


def test_both_counts_a_beam_that_shows_either():
    grid = OccupancyGrid(**{**EXACT, "evidence": "both", "free_below": -0.25}).fit([CORRIDOR] * 2)
    # one echo in free space (row 1), one beam through the wall at row -3 to row -5
    assert grid.novelty([row((0.5, 1.5), (0.5, -4.5))]).tolist() == [1.0]
    assert grid.novelty([row((0.5, 1.5), (0.5, -2.5))]).tolist() == [0.5]


def test_learning_scores_each_scan_before_it_is_learned():
    grid = OccupancyGrid(**{**EXACT, "free_below": -0.25})
    box = row((0.5, 1.5), (0.5, -2.5))
    out = grid.stream([CORRIDOR, box, box, box])
    # the box meets free space once; then its cell, an echo once (+1 - 0.5 = 0.5), is no longer free
    assert out.tolist() == [0.0, 0.5, 0.0, 0.0]
    assert grid.log_odds([[0, 1]]).tolist() == [2.0]                 # -0.5 + 1 + 1 + 1, clamped at 2


def test_a_first_perception_contradicts_nothing():
    assert OccupancyGrid().score_one(CORRIDOR) == 0.0


# ------------------------------------------------------------------ a grid of dictionaries
def reference(learn, score, cell_size=0.1, l_occ=0.85, l_free=-0.4, l_min=-2.0, l_max=3.5, evidence="free",
              free_below=-1.0, occupied_above=0.0, tolerance=1, max_range=10.0):
    """The grid as its docstring says, with a dict of cells: the novelty of each scan of ``learn`` (scored,
    then learned), then of each scan of ``score``."""
    grid = {}

    def rays(x):
        n = (len(x) - 3) // 3
        out = [np.empty(n, dtype=bool)] + [np.empty(n) for _ in range(4)]
        scan_rays(x[0], x[1], x[3:3 + n], x[3 + n:3 + 2 * n], x[3 + 2 * n:], 0.0, cell_size, max_range, 0.0, *out)
        return x[:2], *out

    def novelty(x):
        p, hit, ex, ey, fx, fy = rays(x)
        conflicts = counted = 0
        for k in range(hit.size):
            echo = (math.floor(ex[k] / cell_size), math.floor(ey[k] / cell_size))
            conflict = False
            if evidence != "occupied" and hit[k]:
                conflict = all(grid.get((echo[0] + a, echo[1] + b), 0.0) < free_below
                               for a in range(-tolerance, tolerance + 1) for b in range(-tolerance, tolerance + 1))
            if evidence != "free" and not conflict and not math.isnan(fx[k]):
                for i, j in walk_cells(p, (fx[k], fy[k]), cell_size).tolist():
                    if hit[k] and abs(i - echo[0]) <= tolerance and abs(j - echo[1]) <= tolerance:
                        continue
                    conflict = conflict or grid.get((i, j), 0.0) > occupied_above
            conflicts += conflict
            counted += 1 if evidence != "free" else bool(hit[k])
        return conflicts / counted if counted else 0.0

    def learn_one(x):
        p, hit, ex, ey, fx, fy = rays(x)
        occupied = {(math.floor(ex[k] / cell_size), math.floor(ey[k] / cell_size)) for k in range(hit.size) if hit[k]}
        free = {tuple(c) for k in range(hit.size) if not math.isnan(fx[k])
                for c in walk_cells(p, (fx[k], fy[k]), cell_size).tolist()} - occupied
        for c in occupied:
            grid[c] = min(l_max, grid.get(c, 0.0) + l_occ)
        for c in free:
            grid[c] = max(l_min, grid.get(c, 0.0) + l_free)

    out = []
    for x in learn:
        out.append(novelty(x))
        learn_one(x)
    return np.array(out), np.array([novelty(x) for x in score]), grid


@pytest.mark.parametrize("params", [
    {}, {"evidence": "occupied"}, {"evidence": "both", "free_below": -0.3, "tolerance": 0},
    {"cell_size": 0.25, "l_min": -1.0, "l_max": 1.0, "occupied_above": 0.5, "evidence": "both"},
])
def test_the_compiled_grid_is_the_grid_of_dictionaries(params):
    rows = example_rows(seed=4, n=150)
    rows[100:, 4 + 8] -= 0.7          # a change: one sector's echo nearer, in the free floor
    expected_learning, expected_scores, cells = reference(rows, rows, **params)
    grid = OccupancyGrid(**params)
    np.testing.assert_array_equal(grid.stream(rows), expected_learning)
    np.testing.assert_array_equal(grid.novelty(rows), expected_scores)
    keys = np.array(sorted(cells))
    np.testing.assert_array_equal(grid.log_odds(keys), [cells[tuple(k)] for k in keys.tolist()])
    assert np.count_nonzero(grid.log_odds_) == np.count_nonzero([cells[tuple(k)] for k in keys.tolist()])


def test_the_arrays_grow_with_the_area_seen_and_lose_nothing():
    rows = np.vstack([example_rows(seed=1, n=80) + np.r_[[dx, 0.0, 0.0], np.zeros(8), np.full(8, dx), np.zeros(8)]
                      for dx in np.arange(0.0, 400.0, 20.0)])          # twenty stretches of corridor, 20 m apart
    grid = OccupancyGrid().fit(rows)
    assert grid.n_tiles_ > 16 and grid.tiles_.size >= grid.n_tiles_
    _, expected, _ = reference(rows, rows[::37])
    np.testing.assert_array_equal(grid.novelty(rows[::37]), expected)


# ------------------------------------------------------------------ bounds
def test_sectors_beyond_max_range_are_cut_and_read_as_no_echo():
    far = row((0.5, 30.5), (0.5, -2.5))
    with pytest.warns(MapRangeWarning, match="1 sectors end beyond max_range = 10 m"):
        grid = OccupancyGrid(**EXACT).fit([far])
    assert grid.log_odds([[0, 10], [0, 11], [0, 30]]).tolist() == [-0.5, 0.0, 0.0]


def test_a_scan_touching_more_than_max_scan_cells_is_refused_and_nothing_is_learned():
    grid = OccupancyGrid(**EXACT).fit([CORRIDOR])
    before = grid.log_odds_.copy()
    with pytest.raises(ValueError, match="row 1 would touch .* more than max_scan_cells = 20.*nothing was learned"):
        grid.set_params(max_scan_cells=20).partial_fit([CORRIDOR, row((0.5, 9.5), (0.5, -9.5))])
    np.testing.assert_array_equal(grid.log_odds_, before)
    assert grid.scans_ == 1


def test_a_full_grid_reads_cells_beyond_it_as_unknown_and_says_so():
    rows = [row((x + 0.5, 3.5), (x + 0.5, -2.5), robot=(x + 0.5, 0.5)) for x in range(0, 64, 8)]
    with pytest.warns(GridFullWarning, match="max_cells = 512 cells"):
        grid = OccupancyGrid(**{**EXACT, "max_cells": 512}).fit(rows)
    assert grid.n_tiles_ == 2 and grid.tiles_.size == 2
    assert grid.log_odds([[0, 3], [48, 3]]).tolist() == [1.0, 0.0]
