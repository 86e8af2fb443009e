"""Novelty tasks from simulated runs: learn a familiar environment, then patrol a changed one.

A task is one :class:`~novelty.data.Dataset`: ``train_runs`` traversals
of the familiar environment (``split == "train"``, ``y == 0``), then
``test_runs`` traversals of the test environment (``split == "test"``) in
which a scan is labelled novel (``y == 1``) when one of the named novel
features shaped one of its sonar readings (its ``feature_ids``; see
:class:`~novelty.sonar.ranger.RingEchoes`). This is the inspection use the
paper proposes (Marsland et al., 2000, section 1): train in a section known
to be clean, then flag what is new.

Training runs use run numbers ``0 .. train_runs - 1``; test runs start at
:data:`TEST_RUN_OFFSET`, so a test traversal never shares its random draws
with a training one.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..sonar.environments import get_environment
from ..sonar.simulate import concatenate, simulate_run

__all__ = ["make_task", "TEST_RUN_OFFSET"]

#: First run number of test traversals.
TEST_RUN_OFFSET = 1000


def make_task(name: str, train_env, test_env, novel_ids, *, seed: int = 0, train_runs: int = 3,
              test_runs: int = 1, train_passes: int = 1, description: str = "", **metadata):
    """Build a task dataset (see the module docstring).

    Parameters
    ----------
    name : str
        The dataset's name.
    train_env, test_env : str or Environment
    novel_ids : iterable of str
        Features of ``test_env`` whose perception makes a scan novel.
    seed : int, default=0
    train_runs, test_runs : int
        Traversals of each environment.
    train_passes : int, default=1
        How many times a detector should stream the training part
        (``metadata["train_passes"]``); the runs are already distinct
        traversals, as in the paper's repeated learning trials.
    description : str
    **metadata
        Extra metadata entries.
    """
    for label, v in (("train_runs", train_runs), ("test_runs", test_runs),
                     ("train_passes", train_passes)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise ValueError(f"{label} must be a positive int; got {v!r}.")
    train_env = get_environment(train_env)
    test_env = get_environment(test_env)
    novel = frozenset(novel_ids)
    known = {f.id for f in test_env.world.features}
    missing = novel - known
    if missing:
        raise ValueError(f"Novel features {sorted(missing)} are not in {test_env.name!r}.")
    train = [simulate_run(train_env, seed, r) for r in range(train_runs)]
    test = [simulate_run(test_env, seed, TEST_RUN_OFFSET + r) for r in range(test_runs)]
    parts = []
    for ds, split in [(d, "train") for d in train] + [(d, "test") for d in test]:
        y = np.zeros(len(ds), dtype=np.int64)
        if split == "test":
            y = np.array([1 if f & novel else 0 for f in ds.feature_ids], dtype=np.int64)
        parts.append(_with(ds, y=y, split=np.full(len(ds), split)))
    kept = ("threshold_m", "salient_range_m", "bin_length_m", "encoding", "sensor_angles_deg")
    meta = {k: v for k, v in parts[0].metadata.items() if k in kept}
    meta.update({
        "task": name,
        "description": description,
        "seed": int(seed),
        "train_map": train_env.name,
        "test_map": test_env.name,
        "train_runs": int(train_runs),
        "test_runs": int(test_runs),
        "train_passes": int(train_passes),
        "runs": [r for p in parts for r in p.metadata["runs"]],
        "novel_features": sorted(novel),
        "features": test_env.feature_table(),
        "train_features": train_env.feature_table(),
        "labels": "y = 1 where a test scan's feature_ids include a novel feature",
    })
    meta.update(metadata)
    joined = concatenate(parts, name=name)
    return _with(joined, metadata=meta)


def _with(ds, **changes):
    return replace(ds, **changes)
