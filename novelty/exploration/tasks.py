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
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ..datasets.base import Dataset
from ..sonar.environments import Environment, get_environment
from ..sonar.inspection import DIFFICULTIES, CorridorPlan, generate_corridor
from ..sonar.simulate import concatenate, simulate_run

__all__ = ["Leg", "simulate_exploration", "from_runs", "exposures", "paper_tour", "open_door",
           "patrol", "FAMILIAR"]

#: The tracked-feature label of a familiar scan.
FAMILIAR = ""


@dataclass(frozen=True)
class Leg:
    """One run of an exploration: where, and which of its features are tracked.

    Attributes
    ----------
    environment : str or Environment
    tracked : tuple of str
        Feature ids of the environment whose perception is tracked.
    whole : bool
        Track the environment itself: every scan perceives it (feature id:
        the environment's name).
    """

    environment: object
    tracked: tuple = ()
    whole: bool = False


def exposures(labels: Sequence[Sequence[str]], run) -> tuple[np.ndarray, np.ndarray]:
    """The tracked feature and its exposure count of every scan.

    Parameters
    ----------
    labels : sequence of sequences of str
        The tracked features each scan perceives (empty: familiar).
    run : array-like of int, shape (n_scans,)
        The run of each scan; runs come in order.

    Returns
    -------
    feature : ndarray of str
        The feature each scan counts for (:data:`FAMILIAR` if none).
    exposure : ndarray of int
        How many earlier runs perceived that feature; -1 for familiar scans.

    Examples
    --------
    >>> f, e = exposures([["door"], [], ["door"], ["door", "box"]], [0, 0, 1, 2])
    >>> f.tolist(), e.tolist()
    (['door', '', 'door', 'box'], [0, -1, 1, 0])
    """
    run = np.asarray(run)
    if run.shape != (len(labels),):
        raise ValueError(f"run has shape {run.shape}; expected ({len(labels)},), one run a scan.")
    if run.size and np.any(np.diff(run) < 0):
        raise ValueError("Runs must come in order (run numbers non-decreasing scan by scan).")
    met: dict[str, int] = {}      # feature -> runs that perceived it, before the current one
    in_run: set[str] = set()
    current = None
    feature = np.full(len(labels), FAMILIAR, dtype=object)
    exposure = np.full(len(labels), -1, dtype=np.int64)
    for i, (ids, r) in enumerate(zip(labels, run.tolist())):
        if r != current:
            for f in in_run:
                met[f] = met.get(f, 0) + 1
            in_run, current = set(), r
        ids = sorted(set(ids))
        if not ids:
            continue
        chosen = min(ids, key=lambda f: (met.get(f, 0), f))
        feature[i], exposure[i] = chosen, met.get(chosen, 0)
        in_run.update(ids)
    return feature.astype(str), exposure


def _label(ds: Dataset, leg: Leg, env: Environment, index: int, split: str) -> Dataset:
    tracked = frozenset(leg.tracked)
    if leg.whole:
        labels = [(env.name,)] * len(ds)
    else:
        labels = [tuple(sorted(f & tracked)) for f in ds.feature_ids]
    return replace(ds, run=np.full(len(ds), index, dtype=np.int64), split=np.full(len(ds), split),
                   columns={"environment": np.full(len(ds), env.name), "_labels": np.array(
                       [";".join(x) for x in labels])})


def _finish(name: str, parts: list, warmup: int, plan: list[dict], description: str,
            changes: dict | None = None, **metadata) -> Dataset:
    joined = concatenate(parts, name=name)  # joins the scans, not the columns
    column = lambda key: np.concatenate([p.columns[key] for p in parts])  # noqa: E731
    labels = [tuple(x.split(";")) if x else () for x in column("_labels")]
    feature, exposure = exposures(labels, joined.run)
    columns = {"feature": feature, "exposure": exposure, "environment": column("environment")}
    meta = {k: v for k, v in joined.metadata.items()
            if k in ("threshold_m", "salient_range_m", "bin_length_m", "encoding", "sensor_angles_deg")}
    tracked = sorted({f for leg in plan for f in leg["tracked"]})
    meta.update({
        "task": name,
        "description": description,
        "train_passes": 1,
        "exploration": {"warmup_runs": int(warmup), "runs": plan, "tracked": tracked,
                        "changes": dict(changes or {})},
        "labels": "y = 1 where a scan perceives a tracked feature for the first time",
    })
    meta.update(metadata)
    y = (exposure == 0).astype(np.int64)
    return replace(joined, y=y, columns=columns, metadata=meta)


def simulate_exploration(name: str, legs: Sequence[Leg], *, seed: int = 0, warmup: int = 1,
                         description: str = "", changes: dict | None = None,
                         **metadata) -> Dataset:
    """Simulate the runs of ``legs`` in order; label every scan (see the module docstring).

    Parameters
    ----------
    name : str
    legs : sequence of Leg
        The runs, in order; the first ``warmup`` of them are the warm-up.
    seed : int, default=0
        Run ``i`` is the traversal ``(seed, i)`` of its environment.
    warmup : int, default=1
    description : str
    changes : dict of str to str, optional
        ``{new feature: the feature it replaced}`` (for the re-detection score).
    **metadata
        Extra metadata entries.
    """
    if isinstance(warmup, bool) or not isinstance(warmup, (int, np.integer)) or not 0 < warmup < len(legs):
        raise ValueError(f"warmup must be an int in [1, {len(legs) - 1}] (a run before and after "
                         f"it); got {warmup!r}.")
    parts, plan = [], []
    for i, leg in enumerate(legs):
        env = get_environment(leg.environment)
        known = {f.id for f in env.world.features}
        missing = sorted(set(leg.tracked) - known)
        if missing:
            raise ValueError(f"Tracked features {missing} are not in environment {env.name!r}.")
        ds = simulate_run(env, seed, i)
        parts.append(_label(ds, leg, env, i, "train" if i < warmup else "test"))
        plan.append({"environment": env.name, "simulated_run": i,
                     "tracked": [env.name] if leg.whole else sorted(leg.tracked)})
    return _finish(name, parts, warmup, plan, description, changes, seed=int(seed), **metadata)


def from_runs(runs: Sequence, features: Sequence, *, warmup: int = 1, name: str = "my-exploration",
              environments: Sequence[str] | None = None, changes: dict | None = None) -> Dataset:
    """An exploration task from your own recorded runs.

    Parameters
    ----------
    runs : sequence of array-like, each of shape (n_scans_i, n_sensors)
        The runs, in the order they were driven.
    features : sequence of sequences, one per run
        For each scan of each run, the tracked feature it perceives: a str,
        a collection of str for several, or ``None``/``""`` for a familiar scan.
    warmup : int, default=1
        The first runs, learned before anything is tracked.
    name : str, default="my-exploration"
    environments : sequence of str, optional
        A name per run (default ``"run-<i>"``).
    changes : dict of str to str, optional
        ``{new feature: the feature it replaced}``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> runs = [rng.random((20, 4)) for _ in range(3)]
    >>> seen = [[None] * 20, [None] * 15 + ["box"] * 5, ["box"] * 5 + [None] * 15]
    >>> task = from_runs(runs, seen)
    >>> task.columns["exposure"][[20, 35, 40]].tolist()
    [-1, 0, 1]
    """
    if len(runs) != len(features):
        raise ValueError(f"Got {len(runs)} runs but {len(features)} lists of features; one per run.")
    environments = list(environments) if environments is not None else [f"run-{i}" for i in range(len(runs))]
    if len(environments) != len(runs):
        raise ValueError(f"Got {len(environments)} environment names for {len(runs)} runs.")
    if isinstance(warmup, bool) or not isinstance(warmup, (int, np.integer)) or not 0 < warmup < len(runs):
        raise ValueError(f"warmup must be an int in [1, {len(runs) - 1}]; got {warmup!r}.")
    parts, plan = [], []
    for i, (X, seen, env) in enumerate(zip(runs, features, environments)):
        X = np.asarray(X, dtype=np.float64)
        if X.ndim != 2 or len(seen) != X.shape[0]:
            raise ValueError(f"Run {i}: expected a 2-D array and one feature entry a scan; got "
                             f"shape {X.shape} and {len(seen)} entries.")
        labels = [_as_ids(s) for s in seen]
        parts.append(Dataset(name, X, split=np.full(len(X), "train" if i < warmup else "test"),
                             distance=np.arange(len(X), dtype=np.float64),
                             feature_ids=tuple(frozenset(x) for x in labels),
                             run=np.full(len(X), i, dtype=np.int64),
                             columns={"environment": np.full(len(X), str(env)),
                                      "_labels": np.array([";".join(x) for x in labels])}))
        plan.append({"environment": str(env), "tracked": sorted({f for x in labels for f in x})})
    return _finish(name, parts, warmup, plan, "Recorded runs.", changes)


def _as_ids(label) -> tuple:
    if label is None or (isinstance(label, str) and not label):
        return ()
    if isinstance(label, str):
        return (label,)
    return tuple(sorted(str(x) for x in label))


# ------------------------------------------------------------- named tasks
def paper_tour(seed: int = 0, warmup: int = 3, runs_per_environment: int = 3, control_runs: int = 2):
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
    """
    legs = [Leg("a")] * warmup + [Leg("a-star", ("door-r1-open",))] * runs_per_environment
    legs += [Leg("b", ("door-g",))] * runs_per_environment
    legs += [Leg("c", ("door-c1", "board-1", "board-2"))] * runs_per_environment
    legs += [Leg("control", whole=True)] * control_runs
    return simulate_exploration("exploration-tour", legs, seed=seed, warmup=warmup,
                                description="Learn corridor A, then A*, B, C and the control "
                                            "area, in the paper's order.")


def open_door(seed: int = 0, warmup: int = 3, cycles: int = 5):
    """A door that stays open: learn corridor A, then A* (door opened) alternating with A.

    ``warmup`` runs of A, then ``cycles`` times [a run of A* with the door on
    the right at 3 m open, a run of A]. The tracked feature is the opened
    doorway (``door-r1-open``: the office seen through it and its leaf; its
    frame is unchanged); it recurs every other run.
    """
    if isinstance(cycles, bool) or not isinstance(cycles, (int, np.integer)) or cycles < 1:
        raise ValueError(f"cycles must be a positive int; got {cycles!r}.")
    legs = [Leg("a")] * warmup + [Leg("a-star", ("door-r1-open",)), Leg("a")] * cycles
    return simulate_exploration("exploration-open-door", legs, seed=seed, warmup=warmup,
                                description=f"Learn corridor A; then {cycles} cycles of A* (door "
                                            "opened) and A.")


def patrol(seed: int = 0, difficulty: str = "easy", warmup: int = 3, patrols: int = 6,
           change_at: int = 3, length: float = 18.0):
    """A new object each patrol: a generated corridor, recurring objects, one new object a run.

    ``warmup`` clean runs of a generated corridor
    (:func:`~novelty.sonar.inspection.generate_corridor`), then ``patrols``
    runs, each with two recurring objects (``recurring-0``, ``recurring-1``,
    there on every patrol) and one object never seen before (``new-<p>``),
    drawn from the difficulty's objects (:data:`~novelty.sonar.inspection.DIFFICULTIES`;
    open doors excepted) and placed at least 3 m from the recurring ones. From
    patrol ``change_at`` on, ``recurring-0`` is replaced by an object of
    another kind at the same place (``recurring-0-changed``): a known place
    that changes again, for the re-detection score.
    """
    if difficulty not in DIFFICULTIES:
        raise ValueError(f"Unknown difficulty {difficulty!r}; expected one of {', '.join(DIFFICULTIES)}.")
    for label, v, low in (("patrols", patrols, 1), ("change_at", change_at, 0)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
            raise ValueError(f"{label} must be an int >= {low}; got {v!r}.")
    clean = generate_corridor(seed, length)
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), 0x7A7, list(DIFFICULTIES).index(difficulty)]))
    makers = {k: m for k, m in DIFFICULTIES[difficulty].items() if m is not None}
    recurring = []
    for i in range(2):
        recurring.append(_place(clean, makers, rng, f"recurring-{i}", recurring))
    changed = _swap(clean, recurring[0], makers, rng, "recurring-0-changed")
    legs = [Leg(clean.build())] * warmup
    for p in range(patrols):
        here = [changed if p >= change_at else recurring[0], recurring[1]]
        here.append(_place(clean, makers, rng, f"new-{p}", here))
        env = _with_items(clean, here, f"{clean.name}-patrol-{p}").build()
        legs.append(Leg(env, tuple(item.id for _, item in here)))
    changes = {"recurring-0-changed": "recurring-0"} if change_at < patrols else {}
    return simulate_exploration(
        "exploration-patrol", legs, seed=seed, warmup=warmup, changes=changes,
        description=f"Patrol a generated corridor ({difficulty}): two recurring objects and a new "
                    f"one each patrol; recurring-0 changes at patrol {change_at}.",
        difficulty=difficulty)


def _place(plan: CorridorPlan, makers: dict, rng, id: str, avoid: list, min_separation: float = 3.0):
    """(side, item): an object of a random kind at a random clear place of ``plan``."""
    for _attempt in range(500):
        kind = str(rng.choice(sorted(makers)))
        side = str(rng.choice(["right", "left"]))
        x = float(rng.uniform(1.5, plan.length - 1.5))
        item = replace(makers[kind](0), id=id, x=round(x, 3))
        if all(abs(x - other.x) >= min_separation for _, other in avoid) and _clear(plan, side, item):
            return side, item
    raise RuntimeError(f"Could not place {id!r} in {plan.name}; use a longer corridor.")


def _clear(plan: CorridorPlan, side: str, item, gap: float = 0.3) -> bool:
    a, c = item.extent()
    return all(c + gap < it.extent()[0] or a - gap > it.extent()[1] for it in plan.items(side))


def _swap(plan: CorridorPlan, placed: tuple, makers: dict, rng, id: str) -> tuple:
    """The object at ``placed``'s place replaced by one of another kind."""
    side, item = placed
    kinds = [k for k in sorted(makers) if type(makers[k](0)) is not type(item)
             or makers[k](0).description != item.description]
    for kind in rng.permutation(kinds):
        new = replace(makers[str(kind)](0), id=id, x=item.x)
        if _clear(plan, side, new):
            return side, new
    raise RuntimeError(f"Could not replace {item.id!r} in {plan.name} by an object of another kind.")


def _with_items(plan: CorridorPlan, placed: list, name: str) -> CorridorPlan:
    items = {"right": list(plan.right_items), "left": list(plan.left_items)}
    for side, item in placed:
        items[side].append(item)
    return replace(plan, name=name, right_items=tuple(sorted(items["right"], key=lambda it: it.x)),
                   left_items=tuple(sorted(items["left"], key=lambda it: it.x)))
