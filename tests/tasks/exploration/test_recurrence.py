"""Objects that come and go: who is where on which run, from the labels the tasks carry."""

import numpy as np
import pytest

from novelty.registry import build
from novelty.tasks.exploration import irregular, moving, returning
from novelty.tasks.exploration.recurrence import _irregular_schedule

SHORT = 8.0  # a short corridor keeps the simulation fast


def _runs_with(task, feature):
    return sorted(set(task.run[task.columns["feature"] == feature].tolist()))


@pytest.mark.parametrize("seed", range(20))
def test_irregular_gaps_stay_within_bounds(seed):
    rng = np.random.default_rng(seed)
    runs = _irregular_schedule(rng, 12, 4)
    gaps = np.diff(runs)
    assert runs[0] in (0, 1) and runs[-1] < 12 and len(runs) >= 3
    assert gaps.min() >= 1 and gaps.max() <= 4


def test_a_returning_object_is_absent_then_back():
    task = returning(0, before=2, absence=2, after=1, warmup=1, length=SHORT)
    # run 0 is the warm-up; the object is there on runs 1-2, absent on 3-4, back on 5
    assert _runs_with(task, "returning") == [1, 2, 5]
    back = (task.run == 5) & (task.columns["feature"] == "returning")
    assert set(task.columns["exposure"][back].tolist()) == {2}
    assert task.metadata["exploration"]["returns"] == {"returning": 3}


def test_a_moving_object_is_somewhere_else_every_run():
    task = moving(1, runs=3, warmup=1, length=SHORT)
    assert _runs_with(task, "mover") == [1, 2, 3]
    places = task.metadata["moving_places"]
    assert len(places) == 3 and len({tuple(p) for p in places}) == 3
    assert all(side in ("left", "right") and 1.5 <= x <= SHORT - 1.5 for side, x in places)
    exposure = task.columns["exposure"][task.columns["feature"] == "mover"]
    assert sorted(set(exposure.tolist())) == [0, 1, 2]


def test_the_same_seed_gives_the_same_task():
    a, b = irregular(3, runs=3, warmup=1, length=SHORT), irregular(3, runs=3, warmup=1, length=SHORT)
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.columns["feature"], b.columns["feature"])


def test_registered_by_name():
    assert build("dataset", "exploration-return", before=1, absence=1, after=1, warmup=1,
                 length=SHORT).name == "exploration-return"


@pytest.mark.parametrize("make, kwargs, message", [
    (returning, {"absence": 0}, "absence must be an int >= 1"),
    (irregular, {"max_gap": 0}, "max_gap must be an int >= 1"),
    (moving, {"difficulty": "impossible"}, "Unknown difficulty"),
])
def test_bad_settings_are_refused(make, kwargs, message):
    with pytest.raises(ValueError, match=message):
        make(0, **kwargs)
