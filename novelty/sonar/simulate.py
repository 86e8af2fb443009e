"""Simulate runs through an environment into a :class:`~novelty.datasets.Dataset`.

One run, as in Marsland et al. (2000, section 4.2): the robot drives the
route for 10 m (:mod:`~novelty.sonar.controller`), fires its sonar ring
every ``ring_period`` seconds (:mod:`~novelty.sonar.ranger`), and every
10 cm of travel the preprocessed readings of the rings fired over those
10 cm are averaged into one perception (:mod:`~novelty.sonar.preprocessing`):
about 100 perceptions of 16 values in [0, 1] per run.

Randomness comes only from ``numpy.random.default_rng(SeedSequence([seed,
run]))``. Runs with the same ``(seed, run)`` in two environments therefore
share their random draws (common random numbers): A and A* run 0 differ only
where the geometry differs, which makes paired comparisons sharp.

Shares its name with ``novelty/cli/simulate.py``: the simulator, and the command that runs it (a
command's module is named after the command).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..data import Dataset
from .controller import RunVariation
from .environments import get_environment
from .preprocessing import PAPER_BIN_LENGTH, PAPER_THRESHOLD, bin_by_distance, preprocess
from .ranger import PolaroidRanger
from .robot import NOMAD_200, Robot

__all__ = ["simulate", "simulate_run", "simulate_rings", "RingLog", "write_dataset", "run_rng",
           "concatenate"]


def run_rng(seed: int, run: int) -> np.random.Generator:
    """The generator of run ``run`` under ``seed``."""
    for name, v in (("seed", seed), ("run", run)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
            raise ValueError(f"{name} must be a non-negative int; got {v!r}.")
    return np.random.default_rng(np.random.SeedSequence([int(seed), int(run)]))


@dataclass(frozen=True)
class RingLog:
    """Everything about one run at the level of single sonar rings.

    Attributes
    ----------
    poses : ndarray of shape (n_rings, 3)
    travelled : ndarray of shape (n_rings,)
        Odometry (m) at each ring.
    readings : ndarray of shape (n_rings, n_sonars)
        Ranges as reported (m), noise included; ``max_range`` for no echo.
    clean : ndarray of shape (n_rings, n_sonars)
        Noiseless first-echo ranges (``inf`` for no echo).
    source : ndarray of shape (n_rings, n_sonars)
        0 none, 1 direct, 2 multipath, 3 edge.
    perceived : ndarray of shape (n_rings, n_features) of bool
    trajectory_poses : ndarray of shape (n_steps, 3)
    trajectory_travelled : ndarray of shape (n_steps,)
    """

    poses: np.ndarray
    travelled: np.ndarray
    readings: np.ndarray
    clean: np.ndarray
    source: np.ndarray
    perceived: np.ndarray
    trajectory_poses: np.ndarray
    trajectory_travelled: np.ndarray


def simulate_rings(environment, seed: int = 0, run: int = 0, *,
                   ranger: PolaroidRanger = PolaroidRanger(), robot: Robot = NOMAD_200,
                   variation: RunVariation = RunVariation(),
                   salient_range: float = 2.0) -> RingLog:
    """Drive one run and fire the sonar ring along it (before any averaging)."""
    env = get_environment(environment)
    rng = run_rng(seed, run)
    traj = env.controller.drive(env.world, env.start, env.length, variation, rng, robot)
    phase = rng.uniform(0.0, robot.ring_period)
    times = np.arange(phase, traj.t[-1], robot.ring_period)
    heading = np.unwrap(traj.poses[:, 2])
    poses = np.stack([np.interp(times, traj.t, traj.poses[:, 0]),
                      np.interp(times, traj.t, traj.poses[:, 1]),
                      np.interp(times, traj.t, heading)], axis=1)
    travelled = np.interp(times, traj.t, traj.odometry)
    echoes = ranger.cast(env.world, poses, robot, salient_range)
    readings = ranger.read(echoes.ranges, rng)
    return RingLog(poses, travelled, readings, echoes.ranges, echoes.source, echoes.perceived,
                   traj.poses, traj.odometry)


def simulate_run(environment, seed: int = 0, run: int = 0, *,
                 ranger: PolaroidRanger = PolaroidRanger(), robot: Robot = NOMAD_200,
                 variation: RunVariation = RunVariation(), threshold: float = PAPER_THRESHOLD,
                 bin_length: float = PAPER_BIN_LENGTH, salient_range: float = 2.0):
    """One run as a dataset: one perception per ``bin_length`` of travel.

    ``feature_ids[k]`` holds the features that shaped a reading nearer than
    ``salient_range`` in any ring of scan ``k`` (see
    :meth:`~novelty.sonar.ranger.PolaroidRanger.cast`).
    """
    env = get_environment(environment)
    log = simulate_rings(env, seed, run, ranger=ranger, robot=robot, variation=variation,
                         salient_range=min(salient_range, threshold))
    n_bins = int(round(env.length / bin_length))
    values = preprocess(log.readings, threshold)
    X, member = bin_by_distance(values, log.travelled, bin_length, n_bins)
    ids = [f.id for f in env.world.features]
    feature_ids = []
    for k in range(n_bins):
        rows = member == k
        if not rows.any():  # the bin borrowed its nearest ring
            rows = np.zeros_like(rows)
            rows[int(np.argmin(np.abs(log.travelled - (k + 0.5) * bin_length)))] = True
        seen = log.perceived[rows].any(axis=0)
        feature_ids.append(frozenset(ids[i] for i in np.flatnonzero(seen)))
    distance = (np.arange(n_bins) + 1) * bin_length
    heading = np.unwrap(log.trajectory_poses[:, 2])
    t = log.trajectory_travelled
    poses = np.stack([np.interp(distance, t, log.trajectory_poses[:, 0]),
                      np.interp(distance, t, log.trajectory_poses[:, 1]),
                      np.interp(distance, t, heading)], axis=1)
    return Dataset(
        name=f"paper-{env.name}" if env.name in ("a", "a-star", "b", "c", "control") else env.name,
        X=X,
        distance=distance,
        poses=poses,
        feature_ids=tuple(feature_ids),
        run=np.full(n_bins, run, dtype=np.int64),
        metadata={
            "map": env.name,
            "seed": int(seed),
            "runs": [int(run)],
            "description": env.description,
            "n_rings": int(log.readings.shape[0]),
            "threshold_m": float(threshold),
            "salient_range_m": float(min(salient_range, threshold)),
            "bin_length_m": float(bin_length),
            "encoding": f"1 - min(range, {threshold:g} m) / {threshold:g} m, mean over each "
                        f"{bin_length * 100:g} cm of travel",
            "sensor_angles_deg": [round(float(a), 3) for a in np.degrees(robot.sonar_angles())],
            "features": env.feature_table(),
        },
    )


def simulate(environment, runs: int = 1, seed: int = 0, first_run: int = 0, **options):
    """Simulate ``runs`` consecutive runs (``first_run``, ``first_run + 1``, ...) as one dataset.

    Parameters
    ----------
    environment : str or Environment
        A paper environment's name (``"a"``, ``"paper-a-star"``, ``"A*"``,
        ``"b"``, ``"c"``, ``"control"``) or an :class:`Environment`
        (e.g. a generated inspection corridor).
    runs : int, default=1
    seed : int, default=0
    first_run : int, default=0
    **options
        Passed to :func:`simulate_run` (``ranger``, ``robot``, ``variation``,
        ``threshold``, ``bin_length``).

    Returns
    -------
    Dataset
        Runs in order; ``dataset.run`` tells them apart.

    Examples
    --------
    >>> ds = simulate("a", runs=2, seed=0)
    >>> ds.X.shape, sorted(set(ds.run.tolist()))
    ((200, 16), [0, 1])
    """
    if isinstance(runs, bool) or not isinstance(runs, (int, np.integer)) or runs < 1:
        raise ValueError(f"runs must be a positive int; got {runs!r}.")
    parts = [simulate_run(environment, seed, first_run + i, **options) for i in range(runs)]
    return concatenate(parts)


def concatenate(parts, name: str | None = None, **metadata):
    """Join datasets scan-wise (same sensors); metadata from the first, runs listed."""
    first = parts[0]
    if len(parts) == 1 and name is None and not metadata:
        return first
    cat = lambda attr: None if any(getattr(p, attr) is None for p in parts) else np.concatenate(  # noqa: E731
        [getattr(p, attr) for p in parts])
    meta = dict(first.metadata)
    meta["runs"] = [r for p in parts for r in p.metadata.get("runs", [])]
    meta.update(metadata)
    feature_ids = None
    if all(p.feature_ids is not None for p in parts):
        feature_ids = tuple(f for p in parts for f in p.feature_ids)
    return Dataset(name=name or first.name, X=np.vstack([p.X for p in parts]), y=cat("y"),
                   split=cat("split"), distance=cat("distance"), poses=cat("poses"),
                   feature_ids=feature_ids, run=cat("run"), metadata=meta)


def write_dataset(dataset, path) -> Path:
    """Write ``dataset`` to ``path``: ``.npz`` (all arrays) or ``.csv`` (one row per scan).

    Returns the path written. Other suffixes are refused.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npz":
        dataset.to_npz(path)
    elif suffix == ".csv":
        dataset.to_csv(path)
    else:
        raise ValueError(f"Cannot tell the format of {str(path)!r}: use a .npz or .csv file name.")
    return path
