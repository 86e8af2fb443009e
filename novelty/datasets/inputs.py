"""A simulated task's rows as another input: the paper's ring (as simulated) or the ``points`` input.

The simulated robot (:data:`novelty.sonar.robot.NOMAD_200`) has 16 sonars
at known bearings, each ``sonar_ring_radius`` from its centre, and every
simulated task knows the robot's pose at each scan. :func:`with_inputs`
turns such a task's rings into the ``points`` input of
:mod:`novelty.io.scans.points` (the pose, the ring, each sonar's echo in the
world frame along its axis), the same rows for every detector on the task;
its labels, splits and columns stay as they were.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..data import Dataset
from ..io.scans.points import points_columns, ring_points
from ..sonar.robot import NOMAD_200

__all__ = ["INPUTS", "with_inputs"]

#: The inputs a simulated task offers.
INPUTS = ("ring", "points")


def with_inputs(dataset: Dataset, inputs: str = "ring") -> Dataset:
    """``dataset`` with rows of ``inputs``: as simulated (``"ring"``) or the ``points`` input.

    Examples
    --------
    >>> from novelty.sonar.simulate import simulate
    >>> task = with_inputs(simulate("a", seed=0), "points")
    >>> task.X.shape, task.metadata["inputs"], task.metadata["columns"][:4]
    ((100, 51), 'points', ['x', 'y', 'heading', 'near_0'])
    """
    if inputs not in INPUTS:
        raise ValueError(f"inputs must be one of {', '.join(map(repr, INPUTS))}; got {inputs!r}.")
    if inputs == "ring":
        return dataset
    meta = dataset.metadata
    if dataset.poses is None or "sensor_angles_deg" not in meta or "threshold_m" not in meta:
        raise ValueError(f"{dataset.name}: the points input needs the robot's pose at each scan and its sensors' "
                         "bearings and threshold (a simulated task's poses and metadata); this task has "
                         f"{'no poses' if dataset.poses is None else 'no sensor bearings or threshold'}.")
    bearings = np.deg2rad(np.asarray(meta["sensor_angles_deg"], dtype=np.float64))
    X = ring_points(dataset.X, dataset.poses, bearings, float(meta["threshold_m"]), NOMAD_200.sonar_ring_radius)
    return replace(dataset, X=X, metadata={**meta, "inputs": "points", "columns": points_columns(bearings.size),
                                            "sensor_offset_m": NOMAD_200.sonar_ring_radius})
