"""River's streaming anomaly detectors through the adapter (skipped without river)."""

import numpy as np
import pytest

from novelty.bench import river
from novelty.bench import SuiteError, suite_from_dict

anomaly = pytest.importorskip("river.anomaly", reason="river is not installed (pip install 'novelty-habituation[river]')")

X = np.random.default_rng(0).random((60, 4))


def test_the_adapter_scores_then_learns_each_scan_as_river_does():
    det = river.make("river-hst", random_state=3, n_trees=5, height=4, window_size=20)
    out = det.stream(X)
    ref = anomaly.HalfSpaceTrees(n_trees=5, height=4, window_size=20, seed=3)
    expected = []
    for row in X:
        x = dict(enumerate(row.tolist()))
        expected.append(ref.score_one(x))
        ref.learn_one(x)
    np.testing.assert_array_equal(out, expected)
    np.testing.assert_array_equal(det.novelty(X[:5]), [ref.score_one(dict(enumerate(r.tolist()))) for r in X[:5]])


def test_unknown_names_and_parameters_are_refused():
    with pytest.raises(ValueError, match="known: river-hst"):
        river.make("river-nothing")
    with pytest.raises(ValueError, match="has no parameter 'depth'"):
        river.make("river-hst", depth=3).fit(X)


def test_a_suite_names_river_detectors_like_any_other():
    suite = suite_from_dict({"suite": {"protocol": "exploration"},
                             "detectors": [{"name": "river-hst", "params": {"n_trees": 5}}],
                             "tasks": [{"name": "exploration-open-door"}]})
    assert suite.detectors[0].label == "river-hst"
    with pytest.raises(SuiteError, match="has no parameter"):
        suite_from_dict({"detectors": [{"name": "river-loda", "params": {"trees": 5}}],
                         "tasks": [{"name": "exploration-open-door"}]})


def test_the_river_names_are_the_benchmarks_and_said_to_be_no_registered_detector(capsys):
    import novelty
    from novelty.bench.river import RIVER_MODELS
    from novelty.cli import main
    from novelty.registry import RIVER_DETECTORS, UnknownNameError

    assert set(RIVER_MODELS) == set(RIVER_DETECTORS)
    with pytest.raises(UnknownNameError, match="'river-loda' is not a registered detector: one of River's anomaly "
                                               "detectors, which 'novelty bench' runs by name"):
        novelty.make("river-loda")
    assert main(["list", "detectors"]) == 0
    assert "Not registered, run by 'novelty bench' by name: river-hst, river-loda, river-lof" in capsys.readouterr().out
