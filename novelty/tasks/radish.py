"""Tasks from the Radish robot logs: places met for the first time and again, and virtual objects.

Three public CARMEN logs of a robot with a front laser (180 degrees) driving
through an office building, poses corrected by scan matching, from the Radish
robotics data set repository (Howard & Roy 2003): ``intel`` (Intel Research
Lab, Seattle; 910 scans over 500 m), ``aces`` (ACES building, UT Austin; 440
scans, 323 m) and ``csail`` (MIT CSAIL; 406 scans, 380 m). Nothing is
downloaded: the log is read from ``path=`` (the file, or a folder holding it
or ``radish-carmen-logs/``) or from ``$NOVELTY_DATA_DIR`` (a folder holding
``radish-carmen-logs/``), as the UCI tasks read theirs.

The exploration tasks (``exploration-radish-*``) are
:func:`novelty.tasks.places.revisit_task` of their log with settings fixed
from the sensor and the buildings, never from a detector's scores:

- the ring: the paper's (16 sectors, nearest echo, threshold 4 m; Marsland
  et al. 2000, section 4.1), as every other exploration task's: the
  corridors are about 2 m wide, and half of the laser's readings lie within
  1.6-2.0 m, nine in ten within 4.3 m (5.5 m in aces);
- places of radius 1 m, left beyond 2 m: about the robot's drive between two
  scans (median 0.67, 0.97 and 1.05 m), the finest scale the log resolves,
  and half a corridor's width; poses only (a revisit from the other
  direction counts, although a front laser then sees the other way);
- runs of 100 scans, as the simulated tasks' runs, the first the warm-up.

The objects tasks (``inspection-objects-radish-*`` and
``exploration-objects-radish-*``) are
:func:`~novelty.tasks.objects.object_tasks.inspection_task` and
:func:`~novelty.tasks.objects.object_tasks.exploration_task` on the same
logs, with four objects drawn by the task's seed (sides or diameters 0.3-1
m, boxes and cylinders, beside the robot's path), the paper's ring (16
sectors, nearest echo, 4 m) and the defaults of the task functions: the
inspection learns the first half of the log, its objects seen at least once
before they appear; the exploration warms up on the first 30 % of the log,
its objects passed at least three times after they appear (fewer in
``csail``, whose path comes back to few places: two objects, two passes).

References
----------
Howard, A. & Roy, N. (2003). The Robotics Data Set Repository (Radish).
http://radish.sourceforge.net/

Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Novelty detection on a
mobile robot using habituation. From Animals to Animats 6.
"""

from __future__ import annotations

from ..data import Dataset
from ..io.tables.data_files import resolve_data_file
from .objects.object_tasks import exploration_task, inspection_task
from .places import revisit_task

__all__ = ["RADISH_LOGS", "RADISH_FOLDER", "radish_log", "radish_exploration", "radish_intel", "radish_aces",
           "radish_csail", "radish_objects_inspection", "radish_objects_exploration", "SETTINGS",
           "inspection_objects_intel", "inspection_objects_aces", "inspection_objects_csail",
           "exploration_objects_intel", "exploration_objects_aces", "exploration_objects_csail"]

#: The folder of the logs inside ``$NOVELTY_DATA_DIR`` (or ``path=``).
RADISH_FOLDER = "radish-carmen-logs"
#: The logs by name: their file names.
RADISH_LOGS = {"intel": "intel-corrected.log.gz", "aces": "aces-corrected.log.gz",
               "csail": "csail-corrected.log.gz"}

#: The task's fixed settings (see the module docstring for why).
RADIUS_M, LEAVE_M, RUN_SCANS = 1.0, 2.0, 100


def radish_log(log: str, path=None):
    """The file of Radish log ``log`` from ``path`` or ``$NOVELTY_DATA_DIR``."""
    if log not in RADISH_LOGS:
        raise ValueError(f"Unknown Radish log {log!r}; expected one of {', '.join(RADISH_LOGS)}.")
    return resolve_data_file(path, RADISH_LOGS[log], RADISH_FOLDER, f"Radish {log} log")


def radish_exploration(log: str = "intel", path=None, seed: int = 0) -> Dataset:
    """The exploration task of Radish log ``log``: places met for the first time and again.

    ``seed`` is unused: a recording is what it is (the benchmark gives every task one).
    """
    return revisit_task(radish_log(log, path), radius=RADIUS_M, leave=LEAVE_M, run_scans=RUN_SCANS, warmup=1,
                        name=f"exploration-radish-{log}")


def radish_intel(path=None, seed: int = 0) -> Dataset:
    """Radish log of the Intel Research Lab (910 scans): places met first and again; path= or $NOVELTY_DATA_DIR."""
    return radish_exploration("intel", path, seed)


def radish_aces(path=None, seed: int = 0) -> Dataset:
    """Radish log of the ACES building (440 scans): places met first and again; path= or $NOVELTY_DATA_DIR."""
    return radish_exploration("aces", path, seed)


def radish_csail(path=None, seed: int = 0) -> Dataset:
    """Radish log of MIT CSAIL (406 scans): places met first and again; path= or $NOVELTY_DATA_DIR."""
    return radish_exploration("csail", path, seed)


# ------------------------------------------------------------------ objects
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
