"""The paper's environments and the tasks built from them, as registered datasets.

Each environment factory returns simulated traversals of one of the maps of
Marsland, Nehmzow & Shapiro (2000) (see :mod:`novelty.sonar.environments`):
about 100 scans of 16 values in [0, 1] per 10 m run. ``run`` picks the
traversal: different runs differ as real runs do (start, distance from the
wall, speed, heading jitter, sonar noise), each seeded from ``(seed, run)``,
so the same arguments always give the same data.

The tasks follow the paper's experiments: learn A, then meet a change.
"""

from __future__ import annotations

from ..sonar.simulate import simulate
from .inputs import with_inputs
from .simulated import make_task

__all__ = ["paper_a", "paper_a_star", "paper_b", "paper_c", "paper_control",
           "paper_a_to_a_star", "paper_a_to_b", "paper_a_to_c"]


def _runs(environment: str, run: int, seed: int, runs: int):
    return simulate(environment, runs=runs, seed=seed, first_run=run)


def paper_a(run: int = 0, seed: int = 0, runs: int = 1):
    """Corridor A: 1.7 m, painted breezeblock, wooden doors in recesses, a thin crack near the start.

    Parameters
    ----------
    run : int, default=0
        Which traversal (the first when ``runs > 1``).
    seed : int, default=0
    runs : int, default=1
        Consecutive traversals to return, concatenated (``dataset.run`` tells them apart).
    """
    return _runs("a", run, seed, runs)


def paper_a_star(run: int = 0, seed: int = 0, runs: int = 1):
    """Corridor A* (A with the door on the right at about 3 m opened; see :func:`paper_a`)."""
    return _runs("a-star", run, seed, runs)


def paper_b(run: int = 0, seed: int = 0, runs: int = 1):
    """Corridor B: like A, two doors on the right, the first (door G) inset deeper than any in A."""
    return _runs("b", run, seed, runs)


def paper_c(run: int = 0, seed: int = 0, runs: int = 1):
    """Corridor C: 2.1 m, smooth brick and glass, a deep doorway, low laminated boards, a crack at 7 m."""
    return _runs("c", run, seed, runs)


def paper_control(run: int = 0, seed: int = 0, runs: int = 1):
    """Control area: a large open hall; along a wall, into the middle and back (see :func:`paper_a`)."""
    return _runs("control", run, seed, runs)


def paper_a_to_a_star(seed: int = 0, train_runs: int = 3, test_runs: int = 1, inputs: str = "ring"):
    """Task: learn corridor A, then patrol A* (door opened); scans perceiving the open door are novel.

    The paper's experiment 1 (Marsland et al., 2000, section 5.1). Training:
    ``train_runs`` traversals of A; test: ``test_runs`` traversals of A*,
    ``y = 1`` where the opened doorway, the office seen through it or its
    leaf shaped a reading (its frame is unchanged and not counted).
    """
    return with_inputs(make_task("paper-a-to-a-star", "a", "a-star", ["door-r1-open"], seed=seed,
                     train_runs=train_runs, test_runs=test_runs,
                     description="Learn corridor A, patrol A* (door on the right at 3 m opened)."), inputs)


def paper_a_to_b(seed: int = 0, train_runs: int = 3, test_runs: int = 1, inputs: str = "ring"):
    """Task: learn corridor A, then patrol B; scans perceiving door G (inset deeper than A's) are novel.

    The paper's experiment 2 (section 5.2): in B "the only place where the
    output of the neuron is especially high" was door G, "inset deeper than
    those in the first corridor". Only door G is labelled; the rest of B is
    built like A.
    """
    return with_inputs(make_task("paper-a-to-b", "a", "b", ["door-g"], seed=seed, train_runs=train_runs,
                     test_runs=test_runs,
                     description="Learn corridor A, patrol corridor B (door G inset deeper)."), inputs)


def paper_a_to_c(seed: int = 0, train_runs: int = 3, test_runs: int = 1, inputs: str = "ring"):
    """Task: learn corridor A, then patrol C; the deep doorway and the display boards are labelled novel.

    The paper's experiment 3 (section 5.3) names these as the causes of high
    novelty in C. C's walls (brick, glass) also differ from A's throughout,
    so unlabelled scans of C are not all "normal" in the sense of A: read
    scores on this task with that in mind.
    """
    return with_inputs(make_task("paper-a-to-c", "a", "c", ["door-c1", "board-1", "board-2"], seed=seed,
                     train_runs=train_runs, test_runs=test_runs,
                     description="Learn corridor A, patrol corridor C (deep doorway, boards)."), inputs)
