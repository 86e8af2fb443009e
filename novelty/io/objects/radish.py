"""The objects tasks of the three Radish logs: ``inspection-objects-radish-*`` and ``exploration-objects-radish-*``.

:func:`~novelty.io.objects.tasks.inspection_task` and
:func:`~novelty.io.objects.tasks.exploration_task` on the logs of
:mod:`novelty.io.radish` (read from ``path=`` or ``$NOVELTY_DATA_DIR``),
with four objects drawn by the task's seed (sides or diameters 0.3-1 m,
boxes and cylinders, beside the robot's path), the paper's ring (16
sectors, nearest echo, 4 m) and the defaults of the task functions: the
inspection learns the first half of the log, its objects seen at least once
before they appear; the exploration warms up on the first 30 % of the log,
its objects passed at least three times after they appear (fewer in
``csail``, whose path comes back to few places: two objects, two passes).
"""

from __future__ import annotations

from ...data import Dataset
from ..radish import radish_log
from .tasks import exploration_task, inspection_task

__all__ = ["radish_objects_inspection", "radish_objects_exploration", "SETTINGS", "inspection_objects_intel",
           "inspection_objects_aces", "inspection_objects_csail", "exploration_objects_intel",
           "exploration_objects_aces", "exploration_objects_csail"]

#: Per log, what its drive allows: objects and passes of the exploration task.
SETTINGS = {"intel": {"n_objects": 4, "min_passes": 3}, "aces": {"n_objects": 4, "min_passes": 3},
            "csail": {"n_objects": 2, "min_passes": 2}}


def radish_objects_inspection(log: str = "intel", path=None, seed: int = 0, **options) -> Dataset:
    """The inspection task with objects of Radish log ``log`` (``path=`` or ``$NOVELTY_DATA_DIR``)."""
    return inspection_task(radish_log(log, path), seed=seed, name=f"inspection-objects-radish-{log}",
                           **{"n_objects": 4, **options})


def radish_objects_exploration(log: str = "intel", path=None, seed: int = 0, **options) -> Dataset:
    """The exploration task with objects of Radish log ``log`` (``path=`` or ``$NOVELTY_DATA_DIR``)."""
    return exploration_task(radish_log(log, path), seed=seed, name=f"exploration-objects-radish-{log}",
                            **{**SETTINGS[log], **options})


def inspection_objects_intel(path=None, seed: int = 0, **options) -> Dataset:
    """Radish intel log (910 scans): learn the first half, then find four virtual objects; path= or $NOVELTY_DATA_DIR."""
    return radish_objects_inspection("intel", path, seed, **options)


def inspection_objects_aces(path=None, seed: int = 0, **options) -> Dataset:
    """Radish aces log (440 scans): learn the first half, then find four virtual objects; path= or $NOVELTY_DATA_DIR."""
    return radish_objects_inspection("aces", path, seed, **options)


def inspection_objects_csail(path=None, seed: int = 0, **options) -> Dataset:
    """Radish csail log (406 scans): learn the first half, then find four virtual objects; path= or $NOVELTY_DATA_DIR."""
    return radish_objects_inspection("csail", path, seed, **options)


def exploration_objects_intel(path=None, seed: int = 0, **options) -> Dataset:
    """Radish intel log (910 scans) driven on: four virtual objects met first and again; path= or $NOVELTY_DATA_DIR."""
    return radish_objects_exploration("intel", path, seed, **options)


def exploration_objects_aces(path=None, seed: int = 0, **options) -> Dataset:
    """Radish aces log (440 scans) driven on: four virtual objects met first and again; path= or $NOVELTY_DATA_DIR."""
    return radish_objects_exploration("aces", path, seed, **options)


def exploration_objects_csail(path=None, seed: int = 0, **options) -> Dataset:
    """Radish csail log (406 scans) driven on: two virtual objects met first and again; path= or $NOVELTY_DATA_DIR."""
    return radish_objects_exploration("csail", path, seed, **options)
