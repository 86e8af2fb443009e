"""studies/maps/diagnosis.py: its split of the first-encounter AUC's shortfall, its cells and its trace."""

import numpy as np
import pytest

from novelty.bench.holdout.metrics import roc_auc
from novelty.tasks.objects.shapes import Cylinder
from novelty.maps import habituating_map
from novelty.io.scans.points import example_rows
from novelty.maps.habituating_map import cell_keys

from . import diagnosis


def test_the_pairs_each_familiar_scan_wins_sum_to_the_aucs_shortfall():
    scores = np.array([0.2, 0.6, 0.1, 0.6, 0.9])
    first = np.array([True, True, False, False, False])
    # 0.1 outranks none; 0.6 outranks 0.2 and ties 0.6 (1.5); 0.9 outranks both (2): 3.5 of 6 pairs
    losses = diagnosis.pair_losses(scores, first, ~first)
    assert losses.tolist() == [0.0, 1.5, 2.0]
    assert 1 - losses.sum() / 6 == pytest.approx(roc_auc(scores, first))


def test_cells_pack_as_the_maps_cell_keys_of_their_points():
    points = np.array([[0.1, 0.1], [-0.3, 2.5], [5.9, -7.1]])
    assert diagnosis.pack(np.floor(points / 0.4)).tolist() == cell_keys(points, 0.4).tolist()


def test_a_scan_takes_the_first_class_that_holds():
    flags = {"top_on_object": [True, False, False, False, False, False],
             "first_visit": [True, True, False, False, False, False],
             "top_along": [True, True, True, False, False, False],
             "top_bordered": [True, True, True, True, False, False],
             "top_recent": [True, True, True, True, True, False]}
    trace = {k: np.array(v) for k, v in flags.items()} | {"score": np.zeros(6)}
    assert diagnosis.classify(trace).tolist() == [0, 1, 2, 3, 4, 5]


def test_the_trace_scores_every_scan_as_the_map_streams_it_and_finds_an_objects_echo():
    X = example_rows(seed=5, n=60)
    # a post whose surface passes through scan 45's first echo (behind it, seen from the robot)
    n = (X.shape[1] - 3) // 3
    k = int(np.flatnonzero(X[45, 3:3 + n] > 0)[0])
    end = np.array([X[45, 3 + n + k], X[45, 3 + 2 * n + k]])
    away = (end - X[45, :2]) / np.hypot(*(end - X[45, :2]))
    post = Cylinder("post", x=float(end[0] + 0.2 * away[0]), y=float(end[1] + 0.2 * away[1]), radius=0.2,
                    start=45.0)
    # each sector on its axis: the trace finds an object's cells at the sectors' end points, which a cone
    # (arc, the default "sector") spreads over its arc and may step over
    t = diagnosis.trace(habituating_map(arc=0.0), X, [post], np.arange(60.0))
    np.testing.assert_allclose(t["score"], habituating_map(arc=0.0).stream(X), rtol=0, atol=1e-12)
    assert np.allclose(diagnosis.trace(habituating_map(), X, [post], np.arange(60.0))["score"],
                       habituating_map().stream(X), rtol=0, atol=1e-12)
    assert t["object_cells"][45] >= 1
    assert t["object_cells"][:45].sum() == 0          # not standing yet


@pytest.mark.parametrize("params", [{"tolerance": 0}, {"tolerance": 2, "min_passes": 3}, {"evidence": "hits"},
                                    {"evidence_lag": 10}, {"unseen": 0.4, "tolerance": 0}])
def test_the_trace_reads_the_map_as_its_options_say(params):
    X = example_rows(seed=6, n=60)
    t = diagnosis.trace(habituating_map(**params), X, [], np.arange(60.0))
    np.testing.assert_allclose(t["score"], habituating_map(**params).stream(X), rtol=0, atol=1e-12)


def test_the_reported_seeds_are_refused():
    with pytest.raises(SystemExit):
        diagnosis.main(["--seeds", "100", "3"])
