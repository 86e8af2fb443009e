"""An exploration from runs in order: exposure counts and the user's own runs."""

import numpy as np
import pytest

from novelty.tasks.exploration.runs import exposures, from_runs


def test_exposures_count_earlier_runs_not_scans():
    labels = [["d"], ["d"], [], ["d"], ["b"], [], ["d", "b"], ["b", "d"]]
    feature, exposure = exposures(labels, [0, 0, 0, 1, 1, 2, 3, 3])
    assert feature.tolist() == ["d", "d", "", "d", "b", "", "b", "b"]
    # run 3: d met in runs 0 and 1 (2), b in run 1 (1): the newer, b, is counted
    assert exposure.tolist() == [0, 0, -1, 1, 0, -1, 1, 1]


def test_exposures_refuse_runs_out_of_order():
    with pytest.raises(ValueError, match="in order"):
        exposures([[], []], [1, 0])
    with pytest.raises(ValueError, match="one run a scan"):
        exposures([[], []], [0])


def test_from_runs_labels_a_users_runs():
    rng = np.random.default_rng(0)
    runs = [rng.random((5, 3)) for _ in range(3)]
    seen = [[None] * 5, ["box", "box", None, ("box", "cat"), ""], ["cat"] * 5]
    task = from_runs(runs, seen, warmup=1, environments=["lab", "lab", "lab"])
    assert task.columns["feature"].tolist()[5:] == ["box", "box", "", "box", ""] + ["cat"] * 5
    assert task.columns["exposure"].tolist()[5:] == [0, 0, -1, 0, -1] + [1] * 5
    assert task.feature_ids[8] == frozenset({"box", "cat"})
    np.testing.assert_array_equal(task.X, np.vstack(runs))


@pytest.mark.parametrize("runs, seen, warmup, message", [
    ([np.zeros((2, 2))] * 2, [[None] * 2], 1, "one per run"),
    ([np.zeros((2, 2))] * 2, [[None] * 2, [None]], 1, "one feature entry a scan"),
    ([np.zeros((2, 2))] * 2, [[None] * 2] * 2, 2, "warmup must be"),
])
def test_from_runs_refuses_bad_input(runs, seen, warmup, message):
    with pytest.raises(ValueError, match=message):
        from_runs(runs, seen, warmup=warmup)
