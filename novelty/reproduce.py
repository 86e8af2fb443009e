"""The trial protocol of Marsland, Nehmzow & Shapiro (2000), and its Table 1.

Section 3.2 ("Description of the Experiments") and section 4: trials come in
pairs, a learning run (L) along the 10 m route that trains the filter and saves
it, then a non-learning run (NL) that only records novelty; every run starts
from the model saved after the previous learning run. The order, as in
Table 1:

- experiment 1, environment A: L, NL, L, NL, L, NL from an untrained filter;
- experiment 1, A* (a door opened): NL, L, NL, L, NL from the model learned in A;
- experiment 2, B: NL, L, NL, L, NL from the model learned in A, then the
  control: B scored by a filter trained in the open "control" area;
- experiment 3, C: the same as B.

Each run is a fresh wall-following traversal (new run-to-run variation),
seeded. For each trial the table gives the output of the output neuron
integrated over the run with the resting activity subtracted (0.0476 a step
for the paper's constants) and its maximum.

The paper does not say how long the control filter was trained; here it
learns ``control_runs`` runs of the control area, as many learning runs as A
had (3).
"""

from __future__ import annotations

import copy
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["PAPER_TABLE1", "Trial", "run_protocol", "table1_rows", "table1_markdown", "write_table1_csv"]

#: The paper's Table 1: (experiment, trial, mode, integrated, maximum).
PAPER_TABLE1: tuple[tuple[str, str, str, float, float], ...] = (
    ("A", "1", "L", 9.17, 1.00),
    ("A", "2", "NL", 2.64, 0.53),
    ("A", "3", "L", 1.34, 0.43),
    ("A", "4", "NL", 1.07, 0.42),
    ("A", "5", "L", 0.52, 0.42),
    ("A", "6", "NL", 0.30, 0.12),
    ("A*", "1", "NL", 1.44, 0.65),
    ("A*", "2", "L", 1.45, 0.65),
    ("A*", "3", "NL", 0.37, 0.17),
    ("A*", "4", "L", 0.14, 0.08),
    ("A*", "5", "NL", 0.01, 0.05),
    ("B", "1", "NL", 3.38, 0.65),
    ("B", "2", "L", 1.18, 0.42),
    ("B", "3", "NL", 1.21, 0.42),
    ("B", "4", "L", 0.87, 0.35),
    ("B", "5", "NL", 0.03, 0.08),
    ("B", "Control", "NL", 27.09, 1.00),
    ("C", "1", "NL", 9.68, 0.65),
    ("C", "2", "L", 2.56, 0.65),
    ("C", "3", "NL", 3.06, 0.53),
    ("C", "4", "L", 0.98, 0.42),
    ("C", "5", "NL", 0.29, 0.15),
    ("C", "Control", "NL", 27.75, 1.00),
)

#: Dataset names of the paper's environments.
ENVIRONMENTS = {"A": "paper-a", "A*": "paper-a-star", "B": "paper-b", "C": "paper-c",
                "control": "paper-control"}

TABLE1_COLUMNS = ("experiment", "trial", "mode", "integrated", "maximum", "paper_integrated", "paper_maximum")


@dataclass
class Trial:
    """One run of the protocol and what the output neuron did along it."""

    experiment: str
    trial: str
    mode: str  # "L" or "NL"
    novelty: np.ndarray
    distance: np.ndarray
    resting: float
    run: int
    features: list = field(default_factory=list)

    @property
    def integrated(self) -> float:
        """Output summed over the run, the resting activity subtracted each step."""
        return float(np.sum(self.novelty - self.resting))

    @property
    def maximum(self) -> float:
        return float(np.max(self.novelty))


class _Runner:
    """Keeps the detector, the model files and the run counters of one protocol."""

    def __init__(self, detector: str, seed: int, params: dict, model_dir: Path, load_kwargs: dict):
        import novelty

        self.novelty = novelty
        self.detector = detector
        self.seed = seed
        self.params = params
        self.model_dir = model_dir
        self.load_kwargs = load_kwargs
        self.runs: dict[str, int] = {}
        self.history: dict[int, list[np.ndarray]] = {}

    def fresh(self):
        params = dict(self.params)
        params.setdefault("random_state", self.seed)
        return self.novelty.make(self.detector, **params)

    def traverse(self, env: str):
        from . import datasets

        run = self.runs.get(env, 0)
        self.runs[env] = run + 1
        return datasets.load(ENVIRONMENTS[env], run=run, seed=self.seed, **self.load_kwargs), run

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
        back = self.novelty.load(path)
        if id(det) in self.history:
            self.history[id(back)] = self.history.pop(id(det))
        return back


def _features_of(dataset) -> list:
    return list(dataset.metadata.get("features", []))


def run_protocol(detector: str = "hsom", seed: int = 0, params: dict | None = None,
                 control_runs: int = 3, model_dir: str | Path | None = None,
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
    control_runs : int, default=3
        Learning runs of the control filter in the open area.
    model_dir : path, optional
        Where the model saved after each learning run is written (a
        temporary folder when None).
    **load_kwargs
        Passed to every ``novelty.datasets.load`` (simulator options).
    """
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(model_dir) if model_dir is not None else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        runner = _Runner(detector, seed, dict(params or {}), folder, load_kwargs)
        return _protocol(runner, control_runs)


def _session(runner: _Runner, det, experiment: str, env: str, modes: list[str], trials: list[Trial]):
    for number, mode in enumerate(modes, start=1):
        data, run = runner.traverse(env)
        if mode == "L":
            nov = runner.learn(det, data.X)
            det = runner.save(det, f"{experiment.replace('*', '-star')}-{number}")
        else:
            nov = det.novelty(data.X)
        trials.append(Trial(experiment, str(number), mode, np.asarray(nov, dtype=float),
                            np.asarray(data.distance if data.distance is not None else np.arange(len(data))),
                            _resting(det), run, _features_of(data)))
    return det


def _resting(det) -> float:
    return float(getattr(det, "resting_novelty", 0.0))


def _protocol(runner: _Runner, control_runs: int) -> list[Trial]:
    trials: list[Trial] = []
    det = runner.fresh()
    det = _session(runner, det, "A", "A", ["L", "NL", "L", "NL", "L", "NL"], trials)
    model_a = runner.model_dir / "A-5.npz"
    seen_in_a = list(runner.history.get(id(det), []))

    def from_a():
        start = runner.novelty.load(model_a) if model_a.exists() else copy.deepcopy(det)
        if seen_in_a:
            runner.history[id(start)] = list(seen_in_a)
        return start

    _session(runner, from_a(), "A*", "A*", ["NL", "L", "NL", "L", "NL"], trials)

    control = runner.fresh()
    for number in range(1, control_runs + 1):
        data, _ = runner.traverse("control")
        runner.learn(control, data.X)
        control = runner.save(control, f"control-{number}")

    for env in ("B", "C"):
        _session(runner, from_a(), env, env, ["NL", "L", "NL", "L", "NL"], trials)
        data, run = runner.traverse(env)
        trials.append(Trial(env, "Control", "NL", np.asarray(control.novelty(data.X), dtype=float),
                            np.asarray(data.distance if data.distance is not None else np.arange(len(data))),
                            _resting(control), run, _features_of(data)))
    return trials


def table1_rows(trials: list[Trial]) -> list[dict]:
    """Table 1 rebuilt, one dict per trial, beside the paper's values."""
    paper = {(e, t): (i, m) for e, t, _, i, m in PAPER_TABLE1}
    rows = []
    for tr in trials:
        p_int, p_max = paper.get((tr.experiment, tr.trial), (float("nan"), float("nan")))
        rows.append({"experiment": tr.experiment, "trial": tr.trial, "mode": tr.mode,
                     "integrated": round(tr.integrated, 2), "maximum": round(tr.maximum, 2),
                     "paper_integrated": p_int, "paper_maximum": p_max})
    return rows


def table1_markdown(rows: list[dict]) -> str:
    """Table 1 as a markdown table, ours beside the paper's."""
    lines = ["| Exp (Env) | Trial | Integrated | Maximum | Paper integrated | Paper maximum |",
             "| --- | --- | ---: | ---: | ---: | ---: |"]
    for r in rows:
        label = r["trial"] if r["trial"] == "Control" else f"{r['trial']} ({r['mode']})"
        lines.append(f"| {r['experiment']} | {label} | {r['integrated']:.2f} | {r['maximum']:.2f} | "
                     f"{r['paper_integrated']:.2f} | {r['paper_maximum']:.2f} |")
    return "\n".join(lines)


def write_table1_csv(rows: list[dict], path: str | Path) -> None:
    import csv

    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=TABLE1_COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
