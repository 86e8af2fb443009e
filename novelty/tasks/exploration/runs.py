"""An exploration built from runs in order: simulated legs or the user's own recorded runs.

Every scan gets its tracked feature and that feature's exposure count
(:func:`exposures`); the dataset's fields are described in
:mod:`novelty.tasks.exploration.tours`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ...data import FAMILIAR, Dataset
from ...sonar.environments import Environment, get_environment
from ...sonar.simulate import concatenate, simulate_run

__all__ = ["Leg", "simulate_exploration", "from_runs", "exposures", "FAMILIAR"]


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
