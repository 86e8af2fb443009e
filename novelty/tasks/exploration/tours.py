"""Exploration tasks: a sequence of runs in which features appear, recur and change.

A robot that explores keeps learning: a feature it meets for the first time
should be flagged, and as it recurs it should become familiar, while
something new elsewhere is still flagged (Marsland, Nehmzow & Shapiro 2000,
section 5.1: the burst at A*'s opened door "dies away" over two learning
runs). An exploration task is the data to measure that: runs in order, every
scan labelled with the *tracked feature* it perceives and that feature's
*exposure count*.

Each task is one :class:`~novelty.datasets.Dataset`:

- ``run``: the run's position in the exploration (0, 1, ...);
- ``split``: ``"train"`` for the warm-up runs (the familiar environment,
  learned before anything is tracked), ``"test"`` for the rest;
- ``feature_ids``: every map feature each scan perceives (the simulator's
  ground truth, :func:`novelty.sonar.simulate_run`);
- ``columns["feature"]``: the tracked feature the scan perceives, ``""`` for
  a familiar scan;
- ``columns["exposure"]``: how many earlier runs perceived that feature
  (0 at its first encounter; -1 for a familiar scan);
- ``columns["environment"]``: the environment of the scan's run;
- ``y``: 1 where the scan perceives a tracked feature at its first exposure
  (so the task also runs under the hold-out protocol: learn the warm-up,
  score the rest);
- ``metadata["exploration"]``: the plan (runs, warm-up, tracked features,
  ``changes``: a feature that replaces an earlier one at the same place).

A scan perceiving two tracked features (rare: tracked features stand apart)
counts for the one with fewer exposures, the newer to the robot, ties by
name. A whole environment can be tracked (the paper's open control area):
every scan of such a run perceives the feature named after the environment.

Seeds control every traversal: run ``i`` of an exploration under ``seed``
is :func:`~novelty.sonar.simulate_run` ``(environment, seed, i)``.

Building an exploration from runs (:class:`Leg`, :func:`simulate_exploration`,
:func:`from_runs`, :func:`exposures`) is :mod:`novelty.tasks.exploration.runs`; this
module holds the named tasks and exports those names too.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..inputs import with_inputs
from ..inspection import DIFFICULTIES, CorridorPlan, generate_corridor
from .runs import FAMILIAR, Leg, exposures, from_runs, simulate_exploration  # noqa: F401  (read from here too)

__all__ = ["Leg", "simulate_exploration", "from_runs", "exposures", "paper_tour", "open_door",
           "patrol", "FAMILIAR"]


# ------------------------------------------------------------- named tasks
def paper_tour(seed: int = 0, warmup: int = 3, runs_per_environment: int = 3, control_runs: int = 2,
               inputs: str = "ring"):
    """The paper's tour: learn corridor A, then explore A*, B, C and the open control area.

    The order of Marsland et al. (2000, sections 5.1-5.3): ``warmup`` runs of
    A, then ``runs_per_environment`` runs each of A* (tracked: the opened door
    ``door-r1-open``), B (door G, inset deeper than A's doors, ``door-g``) and
    C (the deep doorway ``door-c1``, the display boards ``board-1``,
    ``board-2``), then ``control_runs`` runs of the open area, tracked as a
    whole (``control``). Unlike the paper, every run is learned (the
    prequential protocol scores each scan before learning it). C's brick and
    glass differ from A's walls throughout, so its untracked scans are not
    familiar in the sense of A: read C's scores with that in mind.
    ``inputs="points"``: the rows of :func:`novelty.tasks.inputs.with_inputs`
    (each environment's own coordinates, overlapping A's).
    """
    legs = [Leg("a")] * warmup + [Leg("a-star", ("door-r1-open",))] * runs_per_environment
    legs += [Leg("b", ("door-g",))] * runs_per_environment
    legs += [Leg("c", ("door-c1", "board-1", "board-2"))] * runs_per_environment
    legs += [Leg("control", whole=True)] * control_runs
    return with_inputs(simulate_exploration("exploration-tour", legs, seed=seed, warmup=warmup,
                                            description="Learn corridor A, then A*, B, C and the control "
                                                        "area, in the paper's order."), inputs)


def open_door(seed: int = 0, warmup: int = 3, cycles: int = 5, inputs: str = "ring"):
    """A door that stays open: learn corridor A, then A* (door opened) alternating with A.

    ``warmup`` runs of A, then ``cycles`` times [a run of A* with the door on
    the right at 3 m open, a run of A]. The tracked feature is the opened
    doorway (``door-r1-open``: the office seen through it and its leaf; its
    frame is unchanged); it recurs every other run. ``inputs``: as
    :func:`paper_tour`'s.
    """
    if isinstance(cycles, bool) or not isinstance(cycles, (int, np.integer)) or cycles < 1:
        raise ValueError(f"cycles must be a positive int; got {cycles!r}.")
    legs = [Leg("a")] * warmup + [Leg("a-star", ("door-r1-open",)), Leg("a")] * cycles
    return with_inputs(simulate_exploration("exploration-open-door", legs, seed=seed, warmup=warmup,
                                            description=f"Learn corridor A; then {cycles} cycles of A* "
                                                        "(door opened) and A."), inputs)


def patrol(seed: int = 0, difficulty: str = "easy", warmup: int = 3, patrols: int = 6,
           change_at: int = 3, length: float = 18.0, inputs: str = "ring"):
    """A new object each patrol: a generated corridor, recurring objects, one new object a run.

    ``warmup`` clean runs of a generated corridor
    (:func:`~novelty.tasks.inspection.generate_corridor`), then ``patrols``
    runs, each with two recurring objects (``recurring-0``, ``recurring-1``,
    there on every patrol) and one object never seen before (``new-<p>``),
    drawn from the difficulty's objects (:data:`~novelty.tasks.inspection.DIFFICULTIES`;
    open doors excepted) and placed at least 3 m from the recurring ones. From
    patrol ``change_at`` on, ``recurring-0`` is replaced by an object of
    another kind at the same place (``recurring-0-changed``): a known place
    that changes again, for the re-detection score. ``recurring-0``'s place is
    drawn where an object of another kind stands clear too. ``inputs``: as
    :func:`paper_tour`'s.
    """
    if difficulty not in DIFFICULTIES:
        raise ValueError(f"Unknown difficulty {difficulty!r}; expected one of {', '.join(DIFFICULTIES)}.")
    for label, v, low in (("patrols", patrols, 1), ("change_at", change_at, 0)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
            raise ValueError(f"{label} must be an int >= {low}; got {v!r}.")
    clean = generate_corridor(seed, length)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), 0x7A7, list(DIFFICULTIES).index(difficulty)]))
    makers = {k: m for k, m in DIFFICULTIES[difficulty].items() if m is not None}
    # recurring-0 is replaced later at the same place, so its place must also clear an object
    # of another kind (a person fits between two doors where a box of 0.6 m may not)
    recurring = [place_object(clean, makers, rng, "recurring-0", [],
                              fits=lambda side, item: bool(_replacements(clean, side, item, makers)))]
    recurring.append(place_object(clean, makers, rng, "recurring-1", recurring))
    changed = _swap(clean, recurring[0], makers, rng, "recurring-0-changed")
    legs = [Leg(clean.build())] * warmup
    for p in range(patrols):
        here = [changed if p >= change_at else recurring[0], recurring[1]]
        here.append(place_object(clean, makers, rng, f"new-{p}", here))
        env = with_items(clean, here, f"{clean.name}-patrol-{p}").build()
        legs.append(Leg(env, tuple(item.id for _, item in here)))
    changes = {"recurring-0-changed": "recurring-0"} if change_at < patrols else {}
    return with_inputs(simulate_exploration(
        "exploration-patrol", legs, seed=seed, warmup=warmup, changes=changes,
        description=f"Patrol a generated corridor ({difficulty}): two recurring objects and a new "
                    f"one each patrol; recurring-0 changes at patrol {change_at}.",
        difficulty=difficulty), inputs)


def place_object(plan: CorridorPlan, makers: dict, rng, id: str, avoid: list, min_separation: float = 3.0,
                 fits=None):
    """(side, item): an object of a random kind at a random clear place of ``plan``.

    ``fits(side, item)``, when given, is a further condition the place must meet.
    """
    for _attempt in range(500):
        kind = str(rng.choice(sorted(makers)))
        side = str(rng.choice(["right", "left"]))
        x = float(rng.uniform(1.5, plan.length - 1.5))
        item = replace(makers[kind](0), id=id, x=round(x, 3))
        if (all(abs(x - other.x) >= min_separation for _, other in avoid) and _clear(plan, side, item)
                and (fits is None or fits(side, item))):
            return side, item
    raise RuntimeError(f"Could not place {id!r} in {plan.name}; use a longer corridor.")


def _clear(plan: CorridorPlan, side: str, item, gap: float = 0.3) -> bool:
    a, c = item.extent()
    return all(c + gap < it.extent()[0] or a - gap > it.extent()[1] for it in plan.items(side))


def _other_kinds(makers: dict, item) -> list[str]:
    return [k for k in sorted(makers) if type(makers[k](0)) is not type(item)
            or makers[k](0).description != item.description]


def _replacements(plan: CorridorPlan, side: str, item, makers: dict) -> list[str]:
    """The kinds other than ``item``'s whose object would stand clear at ``item``'s place."""
    return [k for k in _other_kinds(makers, item) if _clear(plan, side, replace(makers[k](0), x=item.x))]


def _swap(plan: CorridorPlan, placed: tuple, makers: dict, rng, id: str) -> tuple:
    """The object at ``placed``'s place replaced by one of another kind."""
    side, item = placed
    for kind in rng.permutation(_other_kinds(makers, item)):
        new = replace(makers[str(kind)](0), id=id, x=item.x)
        if _clear(plan, side, new):
            return side, new
    raise RuntimeError(f"Could not replace {item.id!r} in {plan.name} by an object of another kind.")


def with_items(plan: CorridorPlan, placed: list, name: str) -> CorridorPlan:
    items = {"right": list(plan.right_items), "left": list(plan.left_items)}
    for side, item in placed:
        items[side].append(item)
    return replace(plan, name=name, right_items=tuple(sorted(items["right"], key=lambda it: it.x)),
                   left_items=tuple(sorted(items["left"], key=lambda it: it.x)))
