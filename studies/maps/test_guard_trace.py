"""studies/maps/guard_trace.py: its trace of a scan's most novel cell, and its refusal of reported seeds."""

import numpy as np
import pytest

from novelty.maps import habituating_map
from novelty.io.scans.points import example_rows

from . import guard_trace as trace


@pytest.mark.parametrize("params", [{"arc": 0.0}, {"tolerance": 0, "unseen": 0.25, "arc": 0.0},
                                    {"evidence": "hits", "cell_size": 0.2, "arc": 0.0}, {}])
def test_the_most_novel_cell_is_the_maps_own_score_with_top_one(params):
    X = example_rows(seed=1, n=80)
    det = habituating_map(top=1, **params).fit(X[:50])
    t = trace.top_cells(det, X[50:])
    np.testing.assert_allclose(t[:, 0], det.novelty(X[50:]), rtol=0, atol=1e-12)
    if det.clusterer.arc == 0:
        # its centre lies in a cell one of the scan's echoes falls in (the corridor's walls at y = +-2); with
        # the default cones (8 sectors: 45 degrees) an echo is spread over an arc that leaves the wall line
        assert np.all(np.abs(np.abs(t[:, 4]) - 2.0) <= det.clusterer.cell_size)


def test_a_cell_centre_is_read_back_from_its_packed_key():
    det = habituating_map(evidence="hits", cell_size=0.5, tolerance=0, top=1)
    # the robot at the origin, one sector with an echo at (1.2, -0.7): cell (2, -2), centre (1.25, -0.75)
    row = [0.0, 0.0, 0.0, 0.5, 1.2, -0.7]
    det.fit([[0.0, 0.0, 0.0, 0.0, 4.0, 0.0]])
    v, y, f, x, yy, n = trace.top_cells(det, np.array([row]))[0]
    assert (v, x, yy) == (1.0, 1.25, -0.75)


@pytest.mark.parametrize("seeds", [["5"], ["105", "0"]])
def test_reported_seeds_are_refused(seeds):
    with pytest.raises(SystemExit, match="reported seeds"):
        trace.main(["--seeds", *seeds])


def test_saturated_shares_count_scans_at_the_threshold_by_label():
    novelty = [1.0, 0.99, 0.5, 0.98, 1.0]
    y = [0, 0, 0, 1, 1]
    assert trace.saturated_shares(novelty, y) == (2 / 3, 1 / 2)


def test_a_map_saturates_on_another_place_and_not_on_the_learned_one():
    # a second drive down the learned corridor (another seed's wander, the same x): its walls' cells were
    # hit; the same drive in a corridor 0.5 m narrower: every wall echo lands where rays had passed and
    # nothing was hit (a surface where free space was), so the map reads the scan as new as it can be
    learned = example_rows(seed=3, n=80)
    det = habituating_map(arc=0.0).fit(np.vstack([learned] * 5))   # five drives: the free space well seen
    again = example_rows(seed=4, n=80)[10:70]
    narrower = again.copy()
    ends_x, ends_y = narrower[:, 3 + 8:3 + 16], narrower[:, 3 + 16:]
    wall = np.abs(ends_y) > 1.99          # an echo off a wall (the others end at 4 m, in free space)
    # the echo moves 0.5 m nearer along its own ray
    across = np.abs(ends_y - narrower[:, [1]])      # from the robot to the wall, across the corridor
    scale = np.where(wall, (across - 0.5) / across, 1.0)
    narrower[:, 3 + 8:3 + 16] = narrower[:, [0]] + (ends_x - narrower[:, [0]]) * scale
    narrower[:, 3 + 16:] = narrower[:, [1]] + (ends_y - narrower[:, [1]]) * scale
    zeros = np.zeros(len(again))
    same, _ = trace.saturated_shares(det.novelty(again), zeros)
    other, _ = trace.saturated_shares(det.novelty(narrower), zeros)
    assert same < 0.2 and other > 0.8, (same, other)
