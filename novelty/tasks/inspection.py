"""Inspection tasks on seeded, generated corridors with inserted novelties, every scan labelled.

The paper's motivating use (Marsland et al., 2000, section 1): a robot
learns a section of building known to be clean, then patrols and flags
what is new. :func:`generate_corridor` draws a corridor from a seed (width,
wall materials, doors and their recess depths, cracks, a junction);
:func:`insert_novelties` adds changes to a copy of it (an open door, a box or
bin against a wall, a person standing, a missing wall panel, a new display
board); :func:`inspection_task` simulates clean training runs and a patrol
of the changed corridor, with ``y = 1`` on the scans that perceive an
inserted feature; :func:`inspection` and its three difficulties are the
registered tasks (``inspection``, ``inspection-easy``, ...).

Difficulty sets which novelties are drawn and how big they are:

- ``"easy"``: large, high-contrast changes: an open door, a wheelie bin,
  a 0.6 m box, a person, a deep missing panel;
- ``"medium"``: a 0.4 m box, a slim person, a 0.3 m missing panel, a thick
  display board;
- ``"hard"``: small, low-contrast changes: a low 0.25 m box (partly below
  the sonar beam), a thin laminated board, a 0.1 m missing panel, a person
  standing back from the wall.

Every size is chosen (approximately the size of the real object), not
taken from a source.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..sonar.environments import Environment, corridor_environment
from ..sonar.layout import Board, Crack, Door, Opening, Person, Protrusion
from .inputs import with_inputs
from .simulated import make_task

__all__ = ["CorridorPlan", "generate_corridor", "insert_novelties", "inspection_task", "DIFFICULTIES",
           "inspection", "inspection_easy", "inspection_medium", "inspection_hard"]

_MATERIALS_RIGHT = ("breezeblock", "brick", "plaster")
_MATERIALS_LEFT = ("breezeblock", "brick", "plaster", "glass")


def _bin(i):
    return Protrusion(f"novel-{i}", 0.0, width=0.6, depth=0.6, height=1.05, material="plaster",
                      inserted=True, description="wheelie bin (plastic) against the wall")


def _box(i, w, d, h, desc):
    return Protrusion(f"novel-{i}", 0.0, width=w, depth=d, height=h, material="cardboard",
                      inserted=True, description=desc)


#: Novelty makers per difficulty: each takes the novelty's index.
DIFFICULTIES = {
    "easy": {
        "open-door": None,
        "bin": _bin,
        "box": lambda i: _box(i, 0.6, 0.6, 0.9, "large box against the wall"),
        "person": lambda i: Person(f"novel-{i}", 0.0, radius=0.22, gap=0.05, inserted=True),
        "missing-panel": lambda i: Opening(f"novel-{i}", 0.0, width=1.2, depth=0.6,
                                           beyond="plaster", kind="opening", inserted=True,
                                           description="missing wall panel (deep cavity)"),
    },
    "medium": {
        "box": lambda i: _box(i, 0.45, 0.4, 0.8, "medium box against the wall"),
        "person": lambda i: Person(f"novel-{i}", 0.0, radius=0.17, gap=0.1, inserted=True,
                                   description="slim person standing by the wall"),
        "missing-panel": lambda i: Opening(f"novel-{i}", 0.0, width=1.0, depth=0.3,
                                           beyond="plaster", kind="opening", inserted=True,
                                           description="missing wall panel"),
        "board": lambda i: Board(f"novel-{i}", 0.0, width=1.2, thickness=0.06, z=(0.5, 1.7),
                                 material="wood", inserted=True,
                                 description="new display board on battens"),
    },
    "hard": {
        "box": lambda i: _box(i, 0.3, 0.25, 0.5, "small low box against the wall"),
        "board": lambda i: Board(f"novel-{i}", 0.0, width=0.9, thickness=0.02, z=(0.6, 1.5),
                                 inserted=True, description="new thin laminated display board"),
        "missing-panel": lambda i: Opening(f"novel-{i}", 0.0, width=0.8, depth=0.1,
                                           beyond="plaster", kind="opening", inserted=True,
                                           description="missing wall panel (shallow)"),
        "person": lambda i: Person(f"novel-{i}", 0.0, radius=0.16, gap=0.35, inserted=True,
                                   description="person standing back from the wall"),
    },
}


@dataclass(frozen=True)
class CorridorPlan:
    """Everything needed to build a generated corridor."""

    name: str
    width: float
    right: str
    left: str
    right_items: tuple
    left_items: tuple
    length: float

    def build(self) -> Environment:
        desc = (f"Generated corridor {self.name}: {self.width:.2f} m wide, {self.right} on the "
                f"right, {self.left} on the left.")
        return corridor_environment(self.name, self.width, self.right, self.left,
                                    self.right_items, self.left_items, desc, length=self.length)

    def items(self, side: str) -> tuple:
        return self.right_items if side == "right" else self.left_items


def _check_int(name, v, low):
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
        raise ValueError(f"{name} must be an int >= {low}; got {v!r}.")


def generate_corridor(seed: int = 0, length: float = 15.0) -> CorridorPlan:
    """A seeded corridor (the clean map of an inspection task).

    Draws: width U(1.5, 2.5) m; wall materials; doors every U(2.5, 5) m on each
    wall with recesses of a corridor-typical depth U(0.05, 0.25) m (each
    door +-0.05 m); up to two cracks; with probability 0.4 a junction with a
    side corridor. Walls run 6 m beyond both ends of the route.
    """
    _check_int("seed", seed, 0)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), 0x5EED]))
    width = float(rng.uniform(1.5, 2.5))
    right = str(rng.choice(_MATERIALS_RIGHT))
    left = str(rng.choice(_MATERIALS_LEFT))
    depth = float(rng.uniform(0.05, 0.25))
    lo, hi = -5.0, length + 5.0
    sides = {"right": [], "left": []}
    for side in ("right", "left"):
        x = lo + float(rng.uniform(0.5, 2.5))
        k = 0
        while x < hi - 1.0:
            d = float(np.clip(depth + rng.uniform(-0.05, 0.05), 0.04, 0.35))
            sides[side].append(Door(f"door-{side[0]}{k}", round(x, 3), width=0.9, depth=round(d, 3)))
            k += 1
            x += float(rng.uniform(2.5, 5.0))
    if rng.random() < 0.4:
        side = str(rng.choice(["right", "left"]))
        x = float(rng.uniform(2.0, length - 2.0))
        w = float(rng.uniform(1.6, 2.2))
        junction = Opening("junction-1", round(x, 3), width=round(w, 3), depth=6.0,
                           beyond=right if side == "right" else left, description="side corridor")
        sides[side] = [it for it in sides[side] if abs(it.x - x) > (w / 2 + 0.45 + 0.1)]
        sides[side].append(junction)
    for c in range(int(rng.integers(0, 3))):
        side = str(rng.choice(["right", "left"]))
        x = float(rng.uniform(0.5, length - 0.5))
        if all(abs(it.x - x) > 0.8 for it in sides[side]):
            sides[side].append(Crack(f"crack-{c}", round(x, 3)))
    return CorridorPlan(f"corridor-{seed}", round(width, 3), right, left,
                        tuple(sorted(sides["right"], key=lambda it: it.x)),
                        tuple(sorted(sides["left"], key=lambda it: it.x)), float(length))


def insert_novelties(plan: CorridorPlan, seed: int = 0, difficulty: str = "easy",
                     n_novelties: int = 2, min_separation: float = 3.0) -> tuple[CorridorPlan, list]:
    """A copy of ``plan`` with ``n_novelties`` inserted changes, and their ids.

    Novelties are placed along the route (1.5 m from either end), at least
    ``min_separation`` metres apart and clear of the corridor's own items,
    so that each is a separate event along the route.
    """
    if difficulty not in DIFFICULTIES:
        raise ValueError(f"Unknown difficulty {difficulty!r}; expected one of {', '.join(DIFFICULTIES)}.")
    _check_int("n_novelties", n_novelties, 1)
    level = list(DIFFICULTIES).index(difficulty)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), 0x0BE1, level]))
    makers = DIFFICULTIES[difficulty]
    items = {"right": list(plan.right_items), "left": list(plan.left_items)}
    placed: list[float] = []
    ids = []
    for i in range(n_novelties):
        for _attempt in range(200):
            kind = str(rng.choice(list(makers)))
            side = str(rng.choice(["right", "left"]))
            if kind == "open-door":
                doors = [it for it in items[side] if isinstance(it, Door) and not it.open
                         and 1.5 <= it.x <= plan.length - 1.5
                         and all(abs(it.x - p) >= min_separation for p in placed)]
                if not doors:
                    continue
                door = doors[int(rng.integers(len(doors)))]
                new = replace(door, id=f"novel-{i}", open=True, box=False, inserted=True,
                              description="door left open")
                items[side] = [new if it is door else it for it in items[side]]
                placed.append(door.x)
                ids.append(new.id)
                break
            x = float(rng.uniform(1.5, plan.length - 1.5))
            item = replace(makers[kind](i), x=round(x, 3))
            a, c = item.extent()
            clear = all(c + 0.3 < it.extent()[0] or a - 0.3 > it.extent()[1] for it in items[side])
            if not clear or any(abs(x - p) < min_separation for p in placed):
                continue
            items[side].append(item)
            placed.append(x)
            ids.append(item.id)
            break
        else:
            raise RuntimeError(f"Could not place novelty {i} in {plan.name}; use fewer novelties "
                               "or a longer corridor.")
    test = replace(plan, name=f"{plan.name}-{difficulty}",
                   right_items=tuple(sorted(items["right"], key=lambda it: it.x)),
                   left_items=tuple(sorted(items["left"], key=lambda it: it.x)))
    return test, ids


def inspection_task(seed: int = 0, difficulty: str = "easy", n_novelties: int = 2,
                    train_runs: int = 3, test_runs: int = 1, length: float = 15.0):
    """Train on clean runs of a generated corridor, patrol it changed (see the module docstring).

    Returns
    -------
    Dataset
        ``split`` ``"train"``/``"test"``, ``y`` on every scan (0 in training),
        ``metadata["novelties"]`` describing what was inserted and where
        (``position``: metres along the route).
    """
    plan = generate_corridor(seed, length)
    test_plan, ids = insert_novelties(plan, seed, difficulty, n_novelties)
    clean, changed = plan.build(), test_plan.build()
    table = {row["id"]: row for row in changed.feature_table()}
    return make_task(
        f"inspection-{difficulty}", clean, changed, ids, seed=seed, train_runs=train_runs,
        test_runs=test_runs,
        description=f"Inspection of generated corridor {seed} ({difficulty}): learn it clean, "
                    f"patrol it with {n_novelties} inserted novelties.",
        difficulty=difficulty,
        novelties=[table[i] for i in ids],
        corridor={"width": plan.width, "right": plan.right, "left": plan.left,
                  "length": plan.length},
    )


# ------------------------------------------------------------------ the registered tasks
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
        The rows: as simulated, or the ``points`` input (:func:`novelty.tasks.inputs.with_inputs`).
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
