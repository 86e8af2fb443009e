"""The objects tasks of the Radish logs (read where the logs are; skipped without them)."""

import numpy as np

from novelty import datasets
from novelty.io.objects.placement import object_from_fields


def test_the_csail_inspection_draws_objects_that_the_robot_sees_after_learning_the_first_half(radish):
    # one object (the registered task draws four, a second and a half more of CPU time)
    task = datasets.load("inspection-objects-radish-csail", path=radish, seed=0, n_objects=1)
    objects = [object_from_fields(o) for o in task.metadata["objects"]]
    assert len(objects) == 1 and {type(o).__name__ for o in objects} <= {"Box", "Cylinder"}
    assert all(0.3 <= (2 * o.radius if hasattr(o, "radius") else max(o.length, o.width)) <= 1.0 for o in objects)
    train, test = task.split == "train", task.split == "test"
    assert train.sum() == 203 and task.metadata["n_recorded_scans"] == 406     # half of the 406 scans
    # the scans that see an object, then the same scans as recorded: as many of each
    twins = test & (task.run == 1)
    assert task.y[test & (task.run == 0)].sum() == twins.sum() > 0 and task.y[twins].sum() == 0
    assert np.array_equal(task.columns["scan"][task.y == 1], task.columns["scan"][twins])
    assert set(task.columns["object"][task.y == 1]) <= {o.name for o in objects}
