"""The habituating map against values computed by hand.

Rows are the ``points`` input (x, y, heading, n nearness values, n end points'
x, then y). With alpha = 1 and tau = 2, one Euler step of equation (1) a scan
halves a hit cell's efficacy: y_k = 2^-k exactly (y_inf = 1 - 1/alpha = 0,
r = 1 - alpha / tau = 1/2; ``visit_gap=0``: every hit a step). Cells are 1 m, the robot stands at (0.1, 0.1), so
that an echo at (2.1, 0.1) lies in cell (2, 0) and its ray, walked up to one
cell short of it (to (1.1, 0.1)), crosses cells (0, 0) and (1, 0).
"""

import math
import tracemalloc

import numpy as np
import pytest

from novelty._component import StateError
from novelty.maps.habituating_map import HabituatingMap, MapRangeWarning, cell_keys, habituating_map, sector_width
from novelty.habituation.stanley import StanleySynapse
from novelty.maps.cells import WorldCells
from novelty.io.scans.points import example_rows
from novelty.persistence import load, save
from tests.damaged import damaging

ROBOT = (0.1, 0.1, 0.0)
EXACT = {"cell_size": 1.0, "tau": 2.0, "alpha": 1.0, "top": 1, "tolerance": 0, "unseen": 0.0, "arc": 0.0,
         "visit_gap": 0}


def scan(*echoes, robot=ROBOT):
    """One points row: a sector for each echo (x, y) in the world; None is a sector with no echo 4 m ahead."""
    near, xs, ys = [], [], []
    for echo in echoes:
        if echo is None:
            near.append(0.0)
            xs.append(robot[0] + 4.0)
            ys.append(robot[1])
        else:
            near.append(1.0 - math.hypot(echo[0] - robot[0], echo[1] - robot[1]) / 4.0)
            xs.append(echo[0])
            ys.append(echo[1])
    return [*robot, *near, *xs, *ys]


def cell(i, j, size=1.0):
    return int(cell_keys([[(i + 0.5) * size, (j + 0.5) * size]], size)[0])


def unit(det, i, j):
    """The unit of cell (i, j), -1 when its tile was never met."""
    return int(det.clusterer_.index().units(np.array([i]), np.array([j]))[0])


def state(det, i, j):
    """(efficacy, passes) of cell (i, j), which the map met."""
    at = unit(det, i, j)
    assert at >= 0 and at in units_met(det), f"cell ({i}, {j}) not met"
    return float(det.synapse_.efficacy_[at]), float(det.clusterer_.passes_[at])


def units_met(det):
    """The units of the cells a scan met: hit, passed or (with neighbours) habituated."""
    c, s = det.clusterer_, det.synapse_
    return np.flatnonzero((c.passes_ > 0) | (c.last_hit_ > 0) | (s.efficacy_ != 1.0))


def met(det):
    """The cells met, packed (cell_keys), increasing."""
    cells = det.clusterer_.cells_of_units(units_met(det))
    return np.sort(cell_keys((cells + 0.5) * det.clusterer_.cell_size, det.clusterer_.cell_size))


def learned(det):
    """Everything the map learned, by name."""
    c = det.clusterer_
    return {"tiles": c.tiles_, "passes": c.passes_, "last_hit": c.last_hit_, "pending": c.pending_,
            "scans": np.array(c.scans_), **{name: getattr(det.synapse_, name) for name in det.synapse_._per_unit}}


# ------------------------------------------------------------------ equation (1)
@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_a_cell_hit_k_times_has_efficacy_two_to_the_minus_k(k):
    det = habituating_map(evidence="hits", **EXACT).fit([scan((2.1, 0.1))] * k)
    assert state(det, 2, 0) == (0.5 ** k, 0.0)
    assert state(det, 0, 0) == state(det, 1, 0) == (1.0, float(k))     # crossed k times, never hit
    assert met(det).tolist() == sorted([cell(0, 0), cell(1, 0), cell(2, 0)])
    assert det.novelty([scan((2.1, 0.1))]).tolist() == [0.5 ** k]


def test_the_papers_synapse_follows_the_closed_form_of_its_euler_steps():
    # y_k = y_inf + (1 - y_inf) (1 - alpha / tau)^k, y_inf = 1 - 1/alpha (tests/habituation/test_stanley.py)
    det = habituating_map(cell_size=1.0, evidence="hits", tau=3.33, alpha=1.05, visit_gap=0).fit([scan((2.1, 0.1))] * 4)
    y_inf = 1 - 1 / 1.05
    assert state(det, 2, 0)[0] == pytest.approx(y_inf + (1 - y_inf) * (1 - 1.05 / 3.33) ** 4, rel=1e-12)


def test_neighbours_habituate_at_their_own_time_constant():
    det = habituating_map(evidence="hits", tau_neighbour=4.0, **EXACT).fit([scan((2.1, 0.1))] * 2)
    assert state(det, 2, 0)[0] == 0.25
    # r = 1 - 1/4: 1 -> 0.75 -> 0.5625, for each of the eight cells around (2, 0)
    assert state(det, 3, 1)[0] == state(det, 1, -1)[0] == 0.5625
    assert met(det).size == 1 + 8 + 1             # and (0, 0), crossed, not a neighbour: held at 1
    assert state(det, 0, 0) == (1.0, 2.0)


# ------------------------------------------------------------------ free-space evidence (2)
def test_an_echo_where_the_robot_saw_free_space_is_novel_by_the_passes_through_its_cell():
    # an echo at (3.1, 0.1), seen twice: its rays cross cells (0, 0) to (2, 0); cell (0, 2) is never met
    det = habituating_map(evidence="free", free_scale=2.0, **EXACT).fit([scan((3.1, 0.1))] * 2)
    assert state(det, 1, 0) == state(det, 2, 0) == (1.0, 2.0)
    v = det.novelty([scan((1.5, 0.1)), scan((0.1, 2.1)), scan((3.1, 0.1))])
    # (1, 0): y = 1 and 2 passes, 1 - exp(-2/2); (0, 2) never seen: no evidence; (3, 0): passes 0
    assert v.tolist() == [1 - math.exp(-1.0), 0.0, 0.0]
    hits = habituating_map(evidence="hits", **EXACT).fit([scan((3.1, 0.1))] * 2)
    assert hits.novelty([scan((1.5, 0.1)), scan((0.1, 2.1)), scan((3.1, 0.1))]).tolist() == [1.0, 1.0, 0.25]


@pytest.mark.parametrize("unseen", [0.0, 0.5, 1.0])
def test_unseen_gives_a_cell_never_seen_through_that_weight(unseen):
    # as above: (1, 0) y = 1 and 2 passes; (0, 2) never met (y = 1, f = 0); (3, 0) hit twice (y = 1/4, f = 0)
    det = habituating_map(free_scale=2.0, **{**EXACT, "unseen": unseen}).fit([scan((3.1, 0.1))] * 2)
    v = det.novelty([scan((1.5, 0.1)), scan((0.1, 2.1)), scan((3.1, 0.1))])
    w = 1 - math.exp(-1.0)
    assert v == pytest.approx([unseen + (1 - unseen) * w, unseen, 0.25 * unseen], rel=1e-12, abs=0)
    if unseen == 1.0:   # u = 1 is the map with hits alone
        hits = habituating_map(evidence="hits", **EXACT).fit([scan((3.1, 0.1))] * 2)
        assert v.tolist() == hits.novelty([scan((1.5, 0.1)), scan((0.1, 2.1)), scan((3.1, 0.1))]).tolist()


def test_a_first_perception_scores_the_unseen_weight():
    assert habituating_map(unseen=0.3).score_one(scan((2.1, 0.1))) == 0.3
    assert habituating_map(unseen=0.0).score_one(scan((2.1, 0.1))) == 0.0
    # a scan met by an empty map: its one cell (2, 0) unseen, weight u, among top = 1
    assert habituating_map(**{**EXACT, "unseen": 0.3}).stream([scan((2.1, 0.1))]).tolist() == [0.3]


def test_a_cell_hit_and_crossed_in_one_scan_counts_as_hit():
    # one sector's echo at (2.1, 0.1) in cell (2, 0); another's ray passes through (2, 0) to (3.9, 0.2)
    det = habituating_map(evidence="hits", **EXACT).fit([scan((2.1, 0.1), (3.9, 0.2))])
    assert state(det, 2, 0) == (0.5, 0.0)
    assert state(det, 1, 0) == (1.0, 1.0)


# ------------------------------------------------------------------ a scan's novelty
def test_a_scans_novelty_is_the_mean_of_its_top_cells_missing_ones_counted_as_zero():
    up, right, left = (0.1, 2.1), (2.1, 0.1), (-1.9, 0.1)
    # efficacies: up 1/2, right 1/4; left never met: 1 (the sectors with no echo only cross cells)
    rows = [scan(up, None, None), scan(None, right, None), scan(None, right, None)]
    seen = scan(up, right, left)
    novelty = {top: habituating_map(evidence="hits", **{**EXACT, "top": top}).fit(rows).novelty([seen])[0]
               for top in (1, 2, 3, 5, None)}
    assert novelty == {1: 1.0, 2: 0.75, 3: 1.75 / 3, 5: 1.75 / 5, None: 1.75 / 3}


def test_a_scan_with_no_echo_scores_zero_and_its_rays_count_as_free_space():
    det = habituating_map(evidence="hits", **EXACT).fit([scan(None)])
    assert det.novelty([scan(None)]).tolist() == [0.0]
    # 4 m ahead, walked to its end (no echo: no cell short of it), (4.1, 0.1): cells 0 to 4 crossed
    assert met(det).tolist() == [cell(i, 0) for i in range(5)]
    assert [state(det, i, 0) for i in range(5)] == [(1.0, 1.0)] * 5


def test_learning_returns_each_scans_novelty_before_it_is_learned():
    det = habituating_map(evidence="hits", **EXACT).fit([scan((2.1, 0.1))])
    assert det.partial_fit([scan((2.1, 0.1))] * 2) is det
    assert state(det, 2, 0)[0] == 0.125
    fresh = habituating_map(evidence="hits", **EXACT).fit([scan((2.1, 0.1))])
    assert fresh.stream([scan((2.1, 0.1))] * 2).tolist() == [0.5, 0.25]


# ------------------------------------------------------------------ the options read more carefully (ours)
@pytest.mark.parametrize("tolerance, expected", [(0, [1.0, 1.0]), (1, [0.5, 1.0]), (2, [0.5, 0.5])])
def test_tolerance_reads_a_cell_as_the_least_efficacy_within_that_many_cells(tolerance, expected):
    # cell (2, 0) hit once: efficacy 1/2; echoes in cells (3, 0) and (4, 0), never met, one and two cells off
    det = habituating_map(evidence="hits", **{**EXACT, "tolerance": tolerance}).fit([scan((2.1, 0.1))])
    assert det.novelty([scan((3.1, 0.1)), scan((4.1, 0.1))]).tolist() == expected
    assert state(det, 2, 0)[0] == 0.5                  # reading only: what is learned is unchanged


def test_the_defaults_are_the_sixth_selections_cells_of_0_1_m_tolerance_1_sector_cones_unseen_a_quarter_visits_of_10():
    # chosen by benchmarks/selection/maps-round6.md (the guard first; cells, tolerance and cones by round 5):
    # cells of 0.1 m read with their neighbours, each scan's sectors as cones as wide as they stand for, a
    # cell never seen through weighing 1/4, a cell habituating once a visit (10 scans without a hit end one)
    det = habituating_map()
    c = det.clusterer
    assert (c.cell_size, c.tolerance, c.arc, c.unseen, c.visit_gap, c.evidence) == \
        (0.1, 1, "sector", 0.25, 10, "free")
    # one sector a scan (no neighbour: read on its axis), the robot at (0.05, 0.05); two scans with an echo
    # at (0.93, 0.05): its cell (9, 0) hit twice in one visit, one step (y = 1/2 with tau = 2, alpha = 1),
    # never crossed; the ray, walked up to 0.1 m short of it (to x = 0.83), crosses (0..8, 0) twice
    robot = (0.05, 0.05, 0.0)
    det = habituating_map(tau=2.0, alpha=1.0, top=1).fit([scan((0.93, 0.05), robot=robot)] * 2)
    v = det.novelty([scan(echo, robot=robot) for echo in ((0.55, 0.05), (0.93, 0.05), (1.03, 0.05), (0.55, 0.35))])
    w = 1 - math.exp(-1.0)
    # (5, 0): y = 1, f = 2; (9, 0): y = 1/2, f = 0; (10, 0), not met, beside the hit cell: read with its
    # neighbours, y = 1/2, f = 0 (1/4 read alone); (5, 3): nothing met within a cell, y = 1, f = 0
    assert v == pytest.approx([0.25 + 0.75 * w, 0.125, 0.125, 0.25], rel=1e-12, abs=0)
    # ten scans that miss (9, 0) end its visit: the next hit is a step (1/2 -> 1/4)
    away = scan((0.05, 0.93), robot=robot)
    det.partial_fit([away] * 10 + [scan((0.93, 0.05), robot=robot)])
    assert det.novelty([scan((0.93, 0.05), robot=robot)]).tolist() == [0.25 * 0.25]
    # a ring of 4 is read as cones of 90 degrees by default
    ring = fan(0.0, math.pi / 2, math.pi, -math.pi / 2)
    cones = habituating_map(arc=math.pi / 2).fit([ring])
    assert np.array_equal(met(habituating_map().fit([ring])), met(cones))
    assert not np.array_equal(met(habituating_map(arc=0.0).fit([ring])), met(cones))


def test_tolerance_looks_along_both_axes_and_the_diagonals():
    det = habituating_map(evidence="hits", **{**EXACT, "tolerance": 1}).fit([scan((1.1, 1.1))])
    # cells (2, 2), (1, 2), (2, 1) touch (1, 1); (3, 1) is two cells off
    assert det.novelty([scan((2.1, 2.1)), scan((1.1, 2.1)), scan((2.1, 1.1)), scan((3.1, 1.1))]).tolist() == \
        [0.5, 0.5, 0.5, 1.0]


@pytest.mark.parametrize("min_passes, expected", [(0, 1 - math.exp(-1.0)), (2, 1 - math.exp(-1.0)), (2.5, 0.0)])
def test_cells_crossed_fewer_than_min_passes_times_give_no_novelty(min_passes, expected):
    # two scans with an echo at (3.1, 0.1): cell (1, 0) crossed twice, never hit
    det = habituating_map(free_scale=2.0, min_passes=min_passes, **EXACT).fit([scan((3.1, 0.1))] * 2)
    assert det.novelty([scan((1.5, 0.1))]).tolist() == [expected]


def test_min_passes_also_holds_with_hits_alone():
    det = habituating_map(evidence="hits", min_passes=1, **EXACT).fit([scan((3.1, 0.1))])
    # (1, 0) crossed once: y = 1 counts; (0, 2) never met: no passes, none
    assert det.novelty([scan((1.5, 0.1)), scan((0.1, 2.1))]).tolist() == [1.0, 0.0]


def test_with_an_evidence_lag_free_space_counts_once_it_is_that_many_scans_old():
    rows = [scan((3.1, 0.1))] * 2
    det = habituating_map(free_scale=2.0, evidence_lag=1, **EXACT).fit(rows)
    # the second scan's free space is pending: (1, 0) has one pass; the hits are learned at once
    assert state(det, 1, 0) == (1.0, 1.0) and state(det, 3, 0) == (0.25, 0.0)
    assert det.clusterer_.pending_.tolist() == [rows[1]]
    assert det.novelty([scan((1.5, 0.1))]).tolist() == [1 - math.exp(-0.5)]
    det.partial_fit([scan((0.6, 0.1))])               # one more scan: the pending one counts now
    assert state(det, 1, 0) == (1.0, 2.0) and det.clusterer_.pending_.tolist() == [scan((0.6, 0.1))]
    assert habituating_map(evidence_lag=2, **EXACT).fit(rows).novelty([scan((1.5, 0.1))]).tolist() == [0.0]


def test_a_scan_is_scored_before_its_own_and_the_pending_free_space_counts():
    # the robot sees through cell (1, 0) on three scans, then an echo lands there
    rows = [scan((3.1, 0.1))] * 3 + [scan((1.5, 0.1))]
    lagged = habituating_map(free_scale=1.0, evidence_lag=2, **EXACT).stream(rows)
    assert lagged.tolist() == [0.0, 0.0, 0.0, 1 - math.exp(-1.0)]
    assert habituating_map(free_scale=1.0, **EXACT).stream(rows).tolist() == [0.0, 0.0, 0.0, 1 - math.exp(-3.0)]


def test_an_evidence_lag_of_zero_is_the_map_without_it():
    X = example_rows(seed=2, n=40)
    lagged, plain = habituating_map(evidence_lag=0).fit(X), habituating_map().fit(X)
    assert np.array_equal(lagged.clusterer_.passes_, plain.clusterer_.passes_) and lagged.clusterer_.pending_.shape == (0, X.shape[1])


# ------------------------------------------------------------------ visits
def test_with_a_visit_gap_a_cell_habituates_once_a_visit():
    hit, away = scan((2.1, 0.1)), scan((0.1, 2.1))
    # cell (2, 0): scans 1-3 one visit (y 1 -> 0.5); scans 4-5 miss it: scan 6 opens a visit (0.25);
    # one miss (scan 7) is not a gap of 2: scan 8 is the same visit. Cell (0, 2): one visit, scans 4-7
    rows = [hit, hit, hit, away, away, hit, away, hit]
    det = habituating_map(evidence="hits", **{**EXACT, "visit_gap": 2})
    assert det.stream(rows).tolist() == [1.0, 0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 0.25]
    assert state(det, 2, 0)[0] == 0.25 and state(det, 0, 2)[0] == 0.5
    assert det.clusterer_.scans_ == 8
    assert det.clusterer_.last_hit_[unit(det, 2, 0)] == 8
    assert det.clusterer_.last_hit_[unit(det, 0, 0)] == 0      # crossed, never hit
    # without it, every hit is a step: 2^-5 after five hits
    assert state(habituating_map(evidence="hits", **EXACT).fit(rows), 2, 0)[0] == 0.5 ** 5


@pytest.mark.parametrize("gap, expected", [(1, 0.25), (3, 0.5)])
def test_a_visit_ends_after_visit_gap_scans_that_miss_the_cell(gap, expected):
    # hits at scans 1 and 4: two misses between them end a visit for a gap of 1, not of 3
    rows = [scan((2.1, 0.1)), scan((0.1, 2.1)), scan((0.1, 2.1)), scan((2.1, 0.1))]
    det = habituating_map(evidence="hits", **{**EXACT, "visit_gap": gap}).fit(rows)
    assert state(det, 2, 0)[0] == expected


def test_fewer_steps_leave_every_cell_at_least_as_novel_as_a_step_a_scan():
    # each step lowers an efficacy above the floor and keeps the order of two (1 - alpha / tau >= 0), so a
    # map that habituates once a visit holds every cell at or above the paper's one step a scan
    X = example_rows(seed=5, n=40)
    visits, scans = habituating_map(visit_gap=3).fit(X), habituating_map(visit_gap=0).fit(X)
    assert np.array_equal(met(visits), met(scans)) and np.array_equal(visits.clusterer_.last_hit_, scans.clusterer_.last_hit_)
    assert np.all(visits.synapse_.efficacy_ >= scans.synapse_.efficacy_)
    assert np.any(visits.synapse_.efficacy_ > scans.synapse_.efficacy_)


def test_with_an_arc_each_echo_is_spread_over_its_cone_at_its_range():
    # arc 0.4 rad, range 2 m, cells 1 m: 1 + ceil(0.4 * 2 / 0.5) = 3 rays at -0.2, 0, 0.2 rad; their ends
    # (2.060, -0.297), (2.1, 0.1), (2.060, 0.497) lie in cells (2, -1) and (2, 0); walked up to one cell
    # short of the echo, to (1.080, -0.099), (1.1, 0.1) and (1.080, 0.299), they cross (0, 0), (0, -1) (the
    # first below y = 0 at x = 0.598), (1, -1), and (1, 0)
    det = habituating_map(evidence="hits", **{**EXACT, "arc": 0.4}).fit([scan((2.1, 0.1))])
    assert met(det).tolist() == sorted([cell(0, -1), cell(0, 0), cell(1, -1), cell(1, 0), cell(2, -1), cell(2, 0)])
    assert state(det, 2, -1) == (0.5, 0.0) and state(det, 2, 0) == (0.5, 0.0)
    assert state(det, 0, -1) == state(det, 0, 0) == state(det, 1, -1) == state(det, 1, 0) == (1.0, 1.0)
    axis = habituating_map(evidence="hits", **EXACT).fit([scan((2.1, 0.1))])
    assert cell(2, -1) not in met(axis) and cell(0, -1) not in met(axis)


def test_with_an_arc_a_sector_without_echo_sees_its_whole_cone_free():
    # 4 m and 0.4 rad: five rays; the one at -0.2 rad passes (3.53, -0.595), in cell (3, -1)
    det = habituating_map(evidence="hits", **{**EXACT, "arc": 0.4}).fit([scan(None)])
    assert state(det, 3, -1) == (1.0, 1.0)
    assert cell(3, -1) not in met(habituating_map(evidence="hits", **EXACT).fit([scan(None)]))


def fan(*bearings, reach=2.0, robot=ROBOT, missing=()):
    """One points row: a sector at each bearing (rad, world frame) with an echo ``reach`` m away, or none
    (nearness 0, its end point 4 m along it) for the indices in ``missing``."""
    near, xs, ys = [], [], []
    for k, b in enumerate(bearings):
        r = 4.0 if k in missing else reach
        near.append(0.0 if k in missing else 1.0 - reach / 4.0)
        xs.append(robot[0] + r * math.cos(b))
        ys.append(robot[1] + r * math.sin(b))
    return [*robot, *near, *xs, *ys]


def ends(row):
    n = (len(row) - 3) // 3
    return np.c_[row[3 + n:3 + 2 * n], row[3 + 2 * n:]]


@pytest.mark.parametrize("bearings, missing, width", [
    ((0.0, math.pi / 2, math.pi, -math.pi / 2), (), math.pi / 2),         # a ring of 4: gaps of 90 degrees
    ((0.0, math.pi / 2, math.pi, -math.pi / 2), (1, 2), math.pi / 2),     # sectors without echo count alike
    ((math.pi / 2, 0.0, -math.pi / 2, math.pi), (), math.pi / 2),         # in any column order
    ((-0.4, 0.0, 0.4), (), 0.4),                                          # a fan: gaps 0.4, 0.4, 2 pi - 0.8
    ((0.0, 0.1), (), math.pi),                                            # gaps 0.1, 2 pi - 0.1: median capped at pi
    ((1.0,), (), 0.0),                                                    # one sector: no neighbour, its axis
])
def test_a_sectors_width_is_the_median_gap_between_the_bearings_round_the_circle(bearings, missing, width):
    assert sector_width(ROBOT, ends(fan(*bearings, missing=missing))) == pytest.approx(width, abs=1e-12)


def test_a_laser_fan_of_180_sectors_over_180_degrees_stands_for_one_degree_and_an_end_at_the_robot_for_none():
    bearings = np.radians(np.arange(180) - 89.5)
    assert sector_width(ROBOT, ends(fan(*bearings))) == pytest.approx(math.radians(1.0), abs=1e-12)
    points = ends(fan(0.0, math.pi / 2, math.pi, -math.pi / 2))
    points[1] = ROBOT[:2]     # no bearing: left out, gaps 180, 90, 90 degrees
    assert sector_width(ROBOT, points) == pytest.approx(math.pi / 2, abs=1e-12)


def test_with_arc_sector_a_fan_is_read_as_cones_as_wide_as_its_sectors():
    # a fan at -0.4, 0, 0.4 rad stands for 0.4 rad a sector: its middle sector's echo at (2.1, 0.1) is spread
    # as in the test of arc = 0.4 above, over cells (2, -1) and (2, 0); on its axis it falls in (2, 0) only
    row = fan(-0.4, 0.0, 0.4)
    det = habituating_map(evidence="hits", **{**EXACT, "arc": "sector"}).fit([row])
    fixed = habituating_map(evidence="hits", **{**EXACT, "arc": 0.4}).fit([row])
    for name, a in learned(det).items():
        assert np.array_equal(a, learned(fixed)[name]), name
    assert state(det, 2, -1) == (0.5, 0.0) and state(det, 2, 0) == (0.5, 0.0)
    axis = habituating_map(evidence="hits", **EXACT).fit([row])
    assert state(axis, 2, 0) == (0.5, 0.0) and cell(2, -1) not in met(axis)


def test_with_arc_sector_each_scan_gets_its_own_width():
    # a ring of 4 seeing a wall ahead only, its ahead sector twice (gaps 0 and four of 90 degrees: median 90),
    # then a fan of 3 ahead with repeats (gaps 0, 0, 0.4, 0.4, 2 pi - 0.8: median 0.4): each is read as with
    # its own fixed arc; the fan's narrow cones stay on the wall the ring's 90-degree cone learned (0.5 each)
    ring = fan(0.0, math.pi / 2, math.pi, -math.pi / 2, 0.0, missing=(1, 2, 3))
    fan3 = fan(-0.4, 0.0, 0.4, 0.4, 0.4)
    mean = {**EXACT, "top": None}     # the mean over every hit cell: the cone's width shows
    det = habituating_map(evidence="hits", **{**mean, "arc": "sector"}).fit([ring])
    fixed = habituating_map(evidence="hits", **{**mean, "arc": math.pi / 2}).fit([ring])
    assert np.array_equal(met(det), met(fixed)) and np.array_equal(det.synapse_.efficacy_, fixed.synapse_.efficacy_)
    wide = fixed.novelty([fan3]).tolist()
    assert det.novelty([fan3]).tolist() == fixed.set_params(arc=0.4).novelty([fan3]).tolist() == [0.5]
    assert wide[0] > 0.5


# ------------------------------------------------------------------ the cells of a scan
def test_a_scans_cells_are_its_hit_cells_centres_with_the_values_its_novelty_is_the_top_mean_of():
    # two echoes in cells (2, 0) and (0, 2) once learned (2^-1 each), a third in cell (-2, 0) never met (1)
    det = habituating_map(**{**EXACT, "evidence": "hits", "top": 2}).fit([scan((2.1, 0.1), (0.1, 2.1), None)])
    row = scan((2.1, 0.1), (0.1, 2.1), (-1.9, 0.1))
    centres, v = det.cell_novelty(row)
    assert sorted(zip(map(tuple, centres.tolist()), v.tolist())) == [
        ((-1.5, 0.5), 1.0), ((0.5, 2.5), 0.5), ((2.5, 0.5), 0.5)]
    assert det.novelty([row])[0] == (1.0 + 0.5) / 2


def test_the_cells_are_read_without_learning_and_agree_with_the_novelty_on_any_map():
    X = example_rows(seed=5, n=80)
    det = habituating_map(tolerance=1, unseen=0.25).fit(X[:60])
    before = det.synapse_.efficacy_.copy()
    for row in X[60:]:
        centres, v = det.cell_novelty(row)
        assert centres.shape == (len(v), 2) and np.array_equal(cell_keys(centres, det.clusterer_.cell_size), np.sort(
            cell_keys(centres, det.clusterer_.cell_size)))
        assert np.sort(v)[-2:].mean() == det.novelty(row[None, :])[0]
    assert np.array_equal(det.synapse_.efficacy_, before)


# ------------------------------------------------------------------ determinism, persistence, refusals
@pytest.mark.parametrize("params", [{"tau_neighbour": 10.0}, {"evidence_lag": 7, "tolerance": 1, "min_passes": 2},
                                    {"visit_gap": 3}])
def test_the_same_rows_give_the_same_map_in_one_batch_or_row_by_row(params):
    X = example_rows(seed=3, n=60)
    batch = habituating_map(**params).fit(X)
    rows = habituating_map(**params).fit(X[:1])
    for row in X[1:]:
        rows.partial_fit(row[None, :])
    for name, a in learned(batch).items():
        assert np.array_equal(a, learned(rows)[name]), name
    assert np.array_equal(batch.novelty(X), habituating_map(**params).fit(X).novelty(X))


def test_a_saved_map_loads_as_the_same_map_from_a_file_without_pickle(tmp_path):
    X = example_rows(seed=1, n=50)
    det = habituating_map(evidence="hits", top=None, tau=30.0).fit(X[:30])
    save(det, tmp_path / "map.npz")
    with np.load(tmp_path / "map.npz", allow_pickle=False) as f:   # refuses any pickled object
        assert len(f.files) > 0
    back = load(tmp_path / "map.npz")
    assert type(back) is HabituatingMap and repr(back.get_params()) == repr(det.get_params())
    assert np.array_equal(met(back), met(det)) and np.array_equal(back.clusterer_.passes_, det.clusterer_.passes_)
    assert np.array_equal(back.novelty(X[30:]), det.novelty(X[30:]))


def test_a_saved_map_keeps_its_pending_scans_and_goes_on_as_the_map_it_was(tmp_path):
    X = example_rows(seed=4, n=50)
    det = habituating_map(evidence_lag=5).fit(X[:30])
    save(det, tmp_path / "map.npz")
    back = load(tmp_path / "map.npz")
    assert np.array_equal(back.clusterer_.pending_, X[25:30])
    assert np.array_equal(back.stream(X[30:]), det.stream(X[30:]))
    assert np.array_equal(back.clusterer_.passes_, det.clusterer_.passes_)


def test_a_saved_map_keeps_its_visits_and_goes_on_as_the_map_it_was(tmp_path):
    X = example_rows(seed=6, n=50)
    det = habituating_map(visit_gap=4).fit(X[:30])
    save(det, tmp_path / "map.npz")
    back = load(tmp_path / "map.npz")
    assert back.clusterer_.scans_ == 30 and np.array_equal(back.clusterer_.last_hit_, det.clusterer_.last_hit_)
    assert np.array_equal(back.stream(X[30:]), det.stream(X[30:]))
    assert np.array_equal(back.synapse_.efficacy_, det.synapse_.efficacy_)


@pytest.mark.parametrize("last, scans", [(31, 30), (-1, 30)])
def test_a_last_hit_outside_the_scans_learned_is_refused_as_a_bad_state(last, scans):
    det = habituating_map(visit_gap=2).fit(example_rows(n=30))
    with damaging(det):
        det.clusterer_.last_hit_[0], det.clusterer_.scans_ = last, scans
    with pytest.raises(StateError, match="last_hit_"):
        det._check_state()


def test_pending_scans_of_another_width_are_refused_as_a_bad_state():
    det = habituating_map(evidence_lag=2).fit(example_rows(n=10))
    with damaging(det):
        det.clusterer_.pending_ = det.clusterer_.pending_[:, :-1]
    with pytest.raises(StateError, match="pending_"):
        det._check_state()


def test_rows_of_another_width_are_refused_naming_the_points_input():
    with pytest.raises(ValueError, match="'points' input"):
        habituating_map().fit([[0.0, 0.0, 0.0, 0.5, 1.0, 2.0, 0.0]])
    det = habituating_map(**EXACT).fit([scan((2.1, 0.1))])
    with pytest.raises(ValueError, match="expecting 6 features"):
        det.novelty([scan((2.1, 0.1), None)])


@pytest.mark.parametrize("row, message", [
    ([0.0, 0.0, 0.0, 1.5, 2.0, 0.0], "nearness in \\[0, 1\\]"),        # a ring value out of range
    ([2e6, 0.0, 0.0, 0.5, 2e6, 0.0], "from the world's origin"),       # not metres in a local frame
])
def test_rows_not_of_the_points_input_are_refused_saying_what_was_expected_and_the_map_is_unchanged(row, message):
    det = habituating_map(**EXACT).fit([scan((2.1, 0.1))])
    before = met(det).copy(), det.synapse_.efficacy_.copy(), det.clusterer_.passes_.copy()
    with pytest.raises(ValueError, match=message):
        det.partial_fit([row])
    with pytest.raises(ValueError, match=message):
        det.novelty([row])
    assert all(np.array_equal(a, b) for a, b in zip(before, (met(det), det.synapse_.efficacy_, det.clusterer_.passes_)))


@pytest.mark.parametrize("params, message", [
    ({"tau": 1.0}, "'tau_winner' parameter of StanleySynapse must be >= alpha"),
    ({"evidence": "both"}, "evidence"),
    ({"top": 0}, "top"),
    ({"cell_size": 0.0}, "cell_size"),
    ({"tolerance": -1}, "tolerance"),
    ({"tolerance": 1.5}, "tolerance"),
    ({"min_passes": -1.0}, "min_passes"),
    ({"evidence_lag": -2}, "evidence_lag"),
    ({"arc": -0.1}, "arc"),
    ({"arc": 4.0}, "arc"),
    ({"arc": "auto"}, "arc"),
    ({"unseen": -0.1}, "unseen"),
    ({"unseen": 1.5}, "unseen"),
    ({"visit_gap": -1}, "visit_gap"),
    ({"visit_gap": 2.5}, "visit_gap"),
])
def test_bad_parameters_are_refused_by_name(params, message):
    with pytest.raises(ValueError, match=message):
        habituating_map(**params).fit([scan((2.1, 0.1))])


def test_cell_keys_increase_with_the_cell_in_row_major_order():
    points = [[-0.1, -0.1], [-0.1, 0.1], [0.1, -0.1], [0.1, 0.1], [0.5, 0.1]]
    keys = cell_keys(points, 0.2)
    assert np.all(np.diff(keys) > 0)
    assert keys[1] - keys[0] == 1 and keys[2] - keys[0] == 2 ** 32


# ------------------------------------------------------------------ the preset
@pytest.mark.parametrize("name, chosen", [
    ("map-explore", {"cell_size": 0.2, "evidence": "free", "free_scale": 2.0, "top": 3, "tolerance": 0, "unseen": 0.5,
                     "arc": 0.0, "neighbours": False, "min_passes": 0, "evidence_lag": 0, "visit_gap": 0,
                     "tau_winner": 3.33, "alpha": 1.05}),
    ("habituating-map", {"cell_size": 0.1, "evidence": "free", "free_scale": 2.0, "top": 2, "tolerance": 1,
                         "unseen": 0.25, "arc": "sector", "neighbours": False, "min_passes": 0, "evidence_lag": 0,
                         "visit_gap": 10, "tau_winner": 3.33, "alpha": 1.05}),
])
def test_a_preset_is_its_settings_written_out_whatever_the_defaults(name, chosen):
    import novelty

    det = novelty.make(name)
    assert isinstance(det, HabituatingMap) and isinstance(det.synapse, StanleySynapse)
    params = {**det.clusterer.get_params(), **det.synapse.get_params()}
    assert {k: params[k] for k in chosen} == chosen
    # every setting of the map is written out but its bounds: no default leaks in
    bounds = {"max_range", "max_scan_cells", "max_cells"}
    assert set(WorldCells().get_params()) - bounds <= set(chosen)
    X = example_rows(seed=2, n=60)
    assert np.array_equal(det.fit(X).novelty(X), HabituatingMap.from_params(**chosen).fit(X).novelty(X))
    # a parameter given replaces its value; the rest stay the preset's
    other = novelty.make(name, tolerance=3, synapse="wang-hsu")
    assert (other.clusterer.tolerance, other.clusterer.cell_size) == (3, chosen["cell_size"])
    assert type(other.synapse).__name__ == "WangHsuSynapse"


def test_the_map_composes_through_the_habituating_construction_with_any_synapse():
    import novelty

    X = example_rows(seed=3, n=40)
    for synapse in ("stanley", "wang-hsu", "staddon-higa"):
        det = novelty.make("habituating", clusterer="world-cells", synapse=synapse, top=3)
        assert isinstance(det, HabituatingMap) and det.clusterer.top == 3
        out = det.stream(X)
        assert out[0] == det.clusterer_.first_novelty(1.0) and np.all((out >= 0) & (out <= 1))
    with pytest.raises(ValueError, match="several winners a scan"):
        novelty.HabituatingFilter(clusterer="world-cells").fit(X)


# ------------------------------------------------------------------ bounds: what one row may cost
def far_row(distance, sectors=180):
    """One points row: the robot at the origin, sectors over its front half, each with an echo ``distance``
    m away (a long-range lidar, or a bad pose)."""
    bearings = np.linspace(-math.pi / 2, math.pi / 2, sectors)
    return [0.0, 0.0, 0.0, *[0.5] * sectors, *(distance * np.cos(bearings)), *(distance * np.sin(bearings))]


def peak_memory_mb(work):
    tracemalloc.start()
    try:
        out = work()
        return out, tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()


def test_echoes_beyond_max_range_are_cut_to_it_and_read_as_no_echo_with_a_warning():
    # end points 100 m, 1 km and 10 km away cost 100 s and 1.9 GB, 18.7 GiB, 1.8 TiB when each ray was
    # sampled every half cell, across its cone too; cut to max_range = 10 m they cost what a 10 m scan costs
    rows = [far_row(100.0), far_row(1e3), far_row(1e4)]
    with pytest.warns(MapRangeWarning, match="540 sectors end beyond max_range = 10 m"):
        det, peak = peak_memory_mb(lambda: habituating_map().fit(rows))
    assert peak < 200
    assert det.synapse_.efficacy_.min() == 1.0                  # no echo learned: each was beyond reach
    i, j = (met(det) >> 32) - (1 << 30), (met(det) & 0xFFFFFFFF) - (1 << 31)
    assert np.hypot(i, j).max() * 0.1 <= 10.0 + 0.2    # every cell met within reach (a cell's diagonal)
    assert det.clusterer_.passes_[units_met(det)].min() >= 1


@pytest.mark.filterwarnings("ignore::novelty.maps.habituating_map.MapRangeWarning")
def test_a_scan_that_would_touch_more_than_max_scan_cells_is_refused_before_anything_is_learned():
    det = habituating_map(max_range=1e4).fit([far_row(2.0)])
    before = (met(det).copy(), det.synapse_.efficacy_.copy(), det.clusterer_.passes_.copy(), det.clusterer_.scans_)
    for distance in (100.0, 1e3, 1e4):
        with pytest.raises(ValueError, match="more than max_scan_cells = 1000000.*nothing was learned"):
            det.partial_fit([far_row(2.0), far_row(distance)])
    assert np.array_equal(met(det), before[0]) and np.array_equal(det.synapse_.efficacy_, before[1])
    assert np.array_equal(det.clusterer_.passes_, before[2]) and det.clusterer_.scans_ == before[3]
    with pytest.raises(ValueError, match="max_scan_cells"):
        det.novelty([far_row(1e4)])


def test_a_ray_costs_the_cells_it_passes_through_linear_in_its_length():
    for distance in (10.0, 100.0, 1000.0):
        det = habituating_map(arc=0.0, max_range=2e3, evidence="hits").fit([far_row(distance, sectors=1)])
        # one ray straight ahead (bearing -pi/2 with one sector: down the y axis), its cells to one short of
        # the echo, and the echo's
        assert met(det).size == round(distance / 0.1) + 1
