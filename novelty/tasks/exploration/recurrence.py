"""Exploration tasks of objects that come and go: irregular recurrence, a long absence, a move.

Each patrols a generated corridor (:func:`~novelty.tasks.inspection.generate_corridor`)
after ``warmup`` clean runs, with objects drawn from a difficulty's objects
(:data:`~novelty.tasks.inspection.DIFFICULTIES`; open doors excepted), and
asks what the exploration tasks of :mod:`novelty.tasks.exploration.tours` do not:

- :func:`irregular`: two objects that recur at irregular intervals (gaps of
  1 to ``max_gap`` runs, drawn from the seed), so habituation meets
  different amounts of recovery between exposures;
- :func:`returning`: an object met on ``before`` runs in a row, then absent
  for ``absence`` runs, then back; a detector that forgets (synapses that
  recover, Stanley 1976) should flag it again on its return, one with a
  long-term memory (Wang & Hsu 1990) re-habituate faster. The return's
  exposure (1-based) is in ``metadata["exploration"]["returns"]``;
- :func:`moving`: one object placed at another place (and wall) on every
  run; the object is the same, its neighbourhood is not.

The settings (gaps, absence, number of runs) are chosen for what each task
asks, not tuned to any detector. Run ``i`` is :func:`~novelty.sonar.simulate_run`
``(environment, seed, i)``, as in every exploration task.
"""

from __future__ import annotations

import numpy as np

from ..inputs import with_inputs
from ..inspection import DIFFICULTIES, generate_corridor
from .runs import Leg, simulate_exploration
from .tours import place_object, with_items

__all__ = ["irregular", "returning", "moving"]


def _setup(seed: int, difficulty: str, length: float, salt: int):
    if difficulty not in DIFFICULTIES:
        raise ValueError(f"Unknown difficulty {difficulty!r}; expected one of {', '.join(DIFFICULTIES)}.")
    clean = generate_corridor(seed, length)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), salt, list(DIFFICULTIES).index(difficulty)]))
    makers = {k: m for k, m in DIFFICULTIES[difficulty].items() if m is not None}
    return clean, rng, makers


def _check(**values) -> None:
    for label, (v, low) in values.items():
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
            raise ValueError(f"{label} must be an int >= {low}; got {v!r}.")


def _legs(clean, warmup: int, placements: list[list]) -> list:
    """``warmup`` clean runs, then one run per list of placed objects (tracked)."""
    legs = [Leg(clean.build())] * warmup
    for p, here in enumerate(placements):
        env = with_items(clean, here, f"{clean.name}-run-{p}").build() if here else clean.build()
        legs.append(Leg(env, tuple(item.id for _, item in here)))
    return legs


def _irregular_schedule(rng, runs: int, max_gap: int) -> list[int]:
    present, r = [], int(rng.integers(0, 2))
    while r < runs:
        present.append(r)
        r += int(rng.integers(1, max_gap + 1))
    return present


def irregular(seed: int = 0, difficulty: str = "easy", warmup: int = 3, runs: int = 12,
              max_gap: int = 4, length: float = 18.0, inputs: str = "ring"):
    """Two objects recurring at irregular intervals along a generated corridor.

    After ``warmup`` clean runs, ``runs`` runs in which each of two objects
    (``irregular-0``, ``irregular-1``, at fixed places at least 3 m apart)
    is present on its own schedule: from run 0 or 1, then after gaps of 1 to
    ``max_gap`` runs drawn from the seed. ``inputs="points"``: the rows of
    :func:`novelty.tasks.inputs.with_inputs` (the robot's pose with each scan).
    """
    _check(warmup=(warmup, 1), runs=(runs, 3), max_gap=(max_gap, 1))
    clean, rng, makers = _setup(seed, difficulty, length, 0x1EE)
    objects = []
    for i in range(2):
        objects.append(place_object(clean, makers, rng, f"irregular-{i}", objects))
    schedules = [set(_irregular_schedule(rng, runs, max_gap)) for _ in objects]
    placements = [[o for o, when in zip(objects, schedules) if r in when] for r in range(runs)]
    return with_inputs(simulate_exploration(
        "exploration-irregular", _legs(clean, warmup, placements), seed=seed, warmup=warmup,
        description=f"Patrol a generated corridor ({difficulty}): two objects recur at irregular "
                    f"intervals (gaps of 1-{max_gap} runs).",
        difficulty=difficulty), inputs)


def returning(seed: int = 0, difficulty: str = "easy", warmup: int = 3, before: int = 3,
              absence: int = 6, after: int = 2, length: float = 18.0, inputs: str = "ring"):
    """An object met on a few runs, absent for several, then back.

    Met on ``before`` runs, absent for ``absence``, back for ``after``. The
    object (``returning``) stays at one place; the runs of its absence
    are clean runs of the corridor. ``metadata["exploration"]["returns"]``
    is ``{"returning": before + 1}``, the exposure of its return. ``inputs``: as
    :func:`irregular`.
    """
    _check(warmup=(warmup, 1), before=(before, 1), absence=(absence, 1), after=(after, 1))
    clean, rng, makers = _setup(seed, difficulty, length, 0x2E7)
    obj = place_object(clean, makers, rng, "returning", [])
    placements = [[obj]] * before + [[]] * absence + [[obj]] * after
    task = simulate_exploration(
        "exploration-return", _legs(clean, warmup, placements), seed=seed, warmup=warmup,
        description=f"Patrol a generated corridor ({difficulty}): an object met on {before} runs, "
                    f"absent for {absence}, then back.",
        difficulty=difficulty)
    task.metadata["exploration"]["returns"] = {"returning": before + 1}
    return with_inputs(task, inputs)


def moving(seed: int = 0, difficulty: str = "easy", warmup: int = 3, runs: int = 6, length: float = 18.0,
           inputs: str = "ring"):
    """One object (``mover``, always of one kind) at a new place on every run.

    ``runs`` runs after the warm-up; ``metadata["moving_places"]`` lists its (wall, position along the
    corridor in m) on each run. ``inputs``: as :func:`irregular`.
    """
    _check(warmup=(warmup, 1), runs=(runs, 1))
    clean, rng, makers = _setup(seed, difficulty, length, 0x30F)
    kind = str(rng.choice(sorted(makers)))
    placements = [[place_object(clean, {kind: makers[kind]}, rng, "mover", [])] for _ in range(runs)]
    return with_inputs(simulate_exploration(
        "exploration-moving", _legs(clean, warmup, placements), seed=seed, warmup=warmup,
        description=f"Patrol a generated corridor ({difficulty}): one {kind} placed anew on every run.",
        difficulty=difficulty, moving_kind=kind,
        moving_places=[[side, item.x] for [(side, item)] in placements]), inputs)
