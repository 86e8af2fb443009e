"""Running the trials of the paper's protocol: learning and non-learning runs in order, models saved between.

The order of the trials and the choices the paper leaves open are described
in :mod:`novelty.reproduce`.

Shares its name with ``novelty/bench/protocol.py``: the paper's protocol and the benchmark's
protocols are two things of one name.
"""

from __future__ import annotations

import copy
import functools
import tempfile
from pathlib import Path
from typing import Any

import novelty
import numpy as np

from .. import datasets
from ..sonar import simulate
from .trial import Trial, is_resting

__all__ = ["run_protocol", "ENVIRONMENTS"]

#: Dataset names of the paper's environments.
ENVIRONMENTS = {"A": "paper-a", "A*": "paper-a-star", "B": "paper-b", "C": "paper-c",
                "control": "paper-control"}



@functools.lru_cache(maxsize=512)
def _traversal(name: str, seed: int, run: int, options: tuple):
    """One simulated run (cached: a protocol run twice, or with another detector, reuses it)."""
    if options:
        return simulate(name, seed=seed, first_run=run, **dict(options))

    return datasets.load(ENVIRONMENTS[name], run=run, seed=seed)


class _Runner:
    """Keeps the detector, the model files and the run counters of one protocol."""

    def __init__(self, detector: str, seed: int, params: dict, model_dir: Path, load_kwargs: dict):
        self.novelty = novelty
        self.detector = detector
        self.seed = seed
        self.params = params
        self.model_dir = model_dir
        self.options = tuple(sorted(load_kwargs.items()))
        self.runs: dict[str, int] = {}
        self.saved: set[Path] = set()
        self.history: dict[int, list[np.ndarray]] = {}

    def fresh(self):
        params = dict(self.params)
        valid = self.novelty.registry.detectors.parameters(self.detector)
        if valid is None or "random_state" in valid:  # None: it checks its parameters itself
            params.setdefault("random_state", self.seed)
        return self.novelty.make(self.detector, **params)

    def traverse(self, env: str):
        run = self.runs.get(env, 0)
        self.runs[env] = run + 1
        return self.data(env, run), run

    def data(self, env: str, run: int):
        return _traversal(env, self.seed, run, self.options)

    def learn(self, det, X: np.ndarray) -> np.ndarray:
        if det.supports_online:
            return det.stream(X)
        # A batch-only detector relearns everything it has been shown, in order.
        seen = self.history.setdefault(id(det), [])
        before = det.novelty(X) if hasattr(det, "n_features_in_") else np.ones(len(X))
        seen.append(X)
        det.fit(np.vstack(seen))
        return before

    def save(self, det, name: str):
        """Save after a learning run and start the next run from the file, as the robot did."""
        path = self.model_dir / f"{name}.npz"
        try:
            det.save(path)
        except (TypeError, ValueError):
            return det  # a detector without a model-file format continues in memory
        self.saved.add(path)
        back = self.novelty.load(path)
        if id(det) in self.history:
            self.history[id(back)] = self.history.pop(id(det))
        return back


def run_protocol(detector: str = "hsom", seed: int = 0, params: dict | None = None,
                 control_runs: int | None = None, model_dir: str | Path | None = None,
                 a_pairs: int | None = 3, max_a_pairs: int = 25, experiments=("A", "A*", "B", "C"),
                 **load_kwargs: Any) -> list[Trial]:
    """Run the paper's whole protocol; return its trials in Table 1's order.

    Parameters
    ----------
    detector : str, default="hsom"
        Registry name of the detector (any registered detector works).
    seed : int, default=0
        Seeds the detector and every traversal.
    params : dict, optional
        Detector parameters.
    control_runs : int, optional
        Learning runs of the control filter in the open area; by default as
        many as A had.
    model_dir : path, optional
        Where the model saved after each learning run is written (a
        temporary folder when None).
    a_pairs : int or None, default=3
        Pairs (L, NL) of trials in A: 3 as in Table 1, or None to continue
        until a non-learning run shows only the resting activity
        (:func:`is_resting`), the paper's rule.
    max_a_pairs : int, default=25
        Most pairs in A when ``a_pairs`` is None.
    experiments : sequence of str, default=("A", "A*", "B", "C")
        Which experiments to run after A (A always runs: the others start
        from its model).
    **load_kwargs
        Simulator options passed to :func:`novelty.sonar.simulate`
        (``variation``, ``ranger``, ``robot``, ``bin_length``, ...).

    Returns
    -------
    list of Trial
        A's trials (numbered on past 6 when more pairs were needed), A*'s,
        B's with its control, C's with its control.
    """
    if a_pairs is not None and (isinstance(a_pairs, bool) or not isinstance(a_pairs, int) or a_pairs < 1):
        raise ValueError(f"a_pairs must be a positive int or None; got {a_pairs!r}.")
    unknown = sorted(set(experiments) - {"A", "A*", "B", "C"})
    if unknown:
        raise ValueError(f"Unknown experiments {unknown}; known: A, A*, B, C.")
    if control_runs is not None and (isinstance(control_runs, bool) or not isinstance(control_runs, int)
                                     or control_runs < 1):
        raise ValueError(f"control_runs must be a positive int or None; got {control_runs!r}.")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(model_dir) if model_dir is not None else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        runner = _Runner(detector, seed, dict(params or {}), folder, load_kwargs)
        return _protocol(runner, control_runs, a_pairs, max_a_pairs, set(experiments))


def _trial(experiment: str, number, mode: str, nov, data, det, run: int) -> Trial:
    distance = data.distance if data.distance is not None else np.arange(1, len(data) + 1) * 0.1
    return Trial(experiment, str(number), mode, np.asarray(nov, dtype=float), np.asarray(distance),
                 _resting(det), run, list(data.metadata.get("features", [])))


def _session(runner: _Runner, det, experiment: str, env: str, modes: list[str], trials: list[Trial],
             first: int = 1, paired_env: str | None = None):
    for number, mode in enumerate(modes, start=first):
        data, run = runner.traverse(env)
        if mode == "L":
            nov = runner.learn(det, data.X)
            det = runner.save(det, f"{experiment.replace('*', '-star')}-{number}")
        else:
            nov = det.novelty(data.X)
        trials.append(_trial(experiment, number, mode, nov, data, det, run))
        if paired_env is not None and mode == "NL":
            trials[-1].paired = np.asarray(det.novelty(runner.data(paired_env, run).X), dtype=float)
    return det


def _resting(det) -> float:
    return float(getattr(det, "resting_novelty", 0.0))


def _learn_a(runner: _Runner, a_pairs: int | None, max_a_pairs: int, trials: list[Trial]):
    """A's pairs of trials; returns the model and the number of learning runs."""
    det = runner.fresh()
    pairs = a_pairs if a_pairs is not None else max_a_pairs
    for k in range(pairs):
        det = _session(runner, det, "A", "A", ["L", "NL"], trials, first=2 * k + 1)
        if a_pairs is None and is_resting(trials[-1]):
            return det, k + 1
    return det, pairs


def _protocol(runner: _Runner, control_runs: int | None, a_pairs: int | None,
              max_a_pairs: int, experiments: set) -> list[Trial]:
    trials: list[Trial] = []
    det, learned = _learn_a(runner, a_pairs, max_a_pairs, trials)
    if not experiments - {"A"}:
        return trials
    model_a = runner.model_dir / f"A-{2 * learned - 1}.npz"
    seen_in_a = list(runner.history.get(id(det), []))

    def from_a():
        start = runner.novelty.load(model_a) if model_a in runner.saved else copy.deepcopy(det)
        if seen_in_a:
            runner.history[id(start)] = list(seen_in_a)
        return start

    if "A*" in experiments:
        _session(runner, from_a(), "A*", "A*", ["NL", "L", "NL", "L", "NL"], trials, paired_env="A")
    if not experiments & {"B", "C"}:
        return trials

    control = runner.fresh()
    for number in range(1, (control_runs or learned) + 1):
        data, _ = runner.traverse("control")
        runner.learn(control, data.X)
        control = runner.save(control, f"control-{number}")

    for env in [e for e in ("B", "C") if e in experiments]:
        _session(runner, from_a(), env, env, ["NL", "L", "NL", "L", "NL"], trials)
        data, run = runner.traverse(env)
        trials.append(_trial(env, "Control", "NL", control.novelty(data.X), data, control, run))
    return trials
