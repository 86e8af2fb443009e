"""Inspection tasks on seeded, generated corridors (see :mod:`novelty.sonar.inspection`)."""

from __future__ import annotations

from ..sonar.inspection import inspection_task
from .inputs import with_inputs

__all__ = ["inspection", "inspection_easy", "inspection_medium", "inspection_hard"]


def inspection(seed: int = 0, difficulty: str = "easy", n_novelties: int = 2, train_runs: int = 3,
               test_runs: int = 1, length: float = 15.0, inputs: str = "ring"):
    """Learn a clean generated corridor, patrol it with inserted novelties; every scan labelled.

    Parameters
    ----------
    seed : int, default=0
        Chooses the corridor, the novelties and every traversal.
    difficulty : {"easy", "medium", "hard"}, default="easy"
        Large, high-contrast novelties (open door, bin, big box, person, deep
        missing panel) down to small, low-contrast ones (low box, thin board,
        shallow missing panel).
    n_novelties : int, default=2
        Inserted changes, at least 3 m apart along the route.
    train_runs : int, default=3
        Clean traversals in the training part (``metadata["train_passes"]`` is 1:
        the runs are distinct traversals, as the paper's repeated trials).
    test_runs : int, default=1
        Traversals of the changed corridor.
    length : float, default=15.0
        Route length (m); 10 scans per metre.
    inputs : {"ring", "points"}, default="ring"
        The rows: as simulated, or the ``points`` input (:func:`novelty.datasets.inputs.with_inputs`).
    """
    return with_inputs(inspection_task(seed, difficulty, n_novelties, train_runs, test_runs, length), inputs)


def inspection_easy(seed: int = 0, n_novelties: int = 2, train_runs: int = 3, test_runs: int = 1,
                    length: float = 15.0, inputs: str = "ring"):
    """Inspection task with large, high-contrast novelties (see :func:`inspection`)."""
    return inspection(seed, "easy", n_novelties, train_runs, test_runs, length, inputs)


def inspection_medium(seed: int = 0, n_novelties: int = 2, train_runs: int = 3, test_runs: int = 1,
                      length: float = 15.0, inputs: str = "ring"):
    """Inspection task with medium-sized novelties (see :func:`inspection`)."""
    return inspection(seed, "medium", n_novelties, train_runs, test_runs, length, inputs)


def inspection_hard(seed: int = 0, n_novelties: int = 2, train_runs: int = 3, test_runs: int = 1,
                    length: float = 15.0, inputs: str = "ring"):
    """Inspection task with small, low-contrast novelties (see :func:`inspection`)."""
    return inspection(seed, "hard", n_novelties, train_runs, test_runs, length, inputs)
