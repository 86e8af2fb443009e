"""The trial protocol of Marsland, Nehmzow & Shapiro (2000), its Table 1 and its figures.

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

The paper continued in A "until a non-learning run showed only the resting
activity" and needed three pairs. ``a_pairs=3`` (the default) keeps Table 1's
count; ``a_pairs=None`` applies the paper's rule instead (:func:`is_resting`),
adding pairs until it holds (at most ``max_a_pairs``), so that A*, B and C
start from a model that has settled in A.

The paper does not say how long the control filter was trained; here it
learns as many runs of the control area as A had learning runs, unless
``control_runs`` says otherwise.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, sections 3-4, Table 1,
figures 4 and 5.
"""

from __future__ import annotations

import copy
import functools
import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["PAPER_TABLE1", "Trial", "run_protocol", "is_resting", "table1_rows", "table1_markdown",
           "write_table1_csv", "write_table1_markdown", "plot_experiment1", "plot_experiments2_3",
           "write_figures", "RESTING_INTEGRATED", "RESTING_MAXIMUM"]

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

#: A non-learning run "shows only the resting activity" (:func:`is_resting`) when its
#: integrated output is at most this and its maximum at most :data:`RESTING_MAXIMUM`.
#: Both lie between the paper's settled run (A trial 6: 0.30, 0.12) and its last
#: unsettled one (A trial 4: 1.07, 0.42).
RESTING_INTEGRATED = 0.5
RESTING_MAXIMUM = 0.2


@dataclass
class Trial:
    """One run of the protocol and what the output neuron did along it.

    ``paired`` is set for the non-learning trials of A*: the novelty the same
    model gives to the traversal of A drawn with the same random numbers
    (the same start, speed and jitter; the door shut), so that ``novelty -
    paired`` is what opening the door changed.
    """

    experiment: str
    trial: str
    mode: str  # "L" or "NL"
    novelty: np.ndarray
    distance: np.ndarray
    resting: float
    run: int
    features: list = field(default_factory=list)
    paired: np.ndarray | None = None

    @property
    def integrated(self) -> float:
        """Output summed over the run, the resting activity subtracted each step."""
        return float(np.sum(self.novelty - self.resting))

    @property
    def maximum(self) -> float:
        return float(np.max(self.novelty))

    @property
    def label(self) -> str:
        """The trial as Table 1 names it: ``"3 (L)"`` or ``"Control"``."""
        return self.trial if self.trial == "Control" else f"{self.trial} ({self.mode})"

    def near(self, position: float, half_width: float = 1.0) -> np.ndarray:
        """Mask of the scans taken within ``half_width`` metres of ``position`` along the route."""
        return np.abs(self.distance - position) <= half_width


def is_resting(trial: Trial, integrated: float = RESTING_INTEGRATED,
               maximum: float = RESTING_MAXIMUM) -> bool:
    """Whether a run shows only the resting activity of the output neuron.

    The paper's criterion for having learned an environment (section 3.2):
    "the output of the novelty filter was only the resting activity of the
    output neuron throughout the run". In numbers: at most ``integrated``
    above the resting activity over the run and no scan above ``maximum``.

    >>> flat = Trial("A", "6", "NL", np.full(100, 0.0476), np.arange(1, 101) / 10, 0.0476, run=5)
    >>> is_resting(flat), round(flat.integrated, 6)
    (True, 0.0)
    >>> flat.novelty[30] = 0.42  # one scan still novel
    >>> is_resting(flat)
    False
    """
    return trial.integrated <= integrated and trial.maximum <= maximum


@functools.lru_cache(maxsize=512)
def _traversal(name: str, seed: int, run: int, options: tuple):
    """One simulated run (cached: a protocol run twice, or with another detector, reuses it)."""
    if options:
        from .sonar import simulate

        return simulate(name, seed=seed, first_run=run, **dict(options))
    from . import datasets

    return datasets.load(ENVIRONMENTS[name], run=run, seed=seed)


class _Runner:
    """Keeps the detector, the model files and the run counters of one protocol."""

    def __init__(self, detector: str, seed: int, params: dict, model_dir: Path, load_kwargs: dict):
        import novelty

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


# ----------------------------------------------------------------------- Table 1
def table1_rows(trials: list[Trial]) -> list[dict]:
    """Table 1 rebuilt, one dict per trial, beside the paper's values (NaN where it has none)."""
    paper = {(e, t): (i, m) for e, t, _, i, m in PAPER_TABLE1}
    rows = []
    for tr in trials:
        p_int, p_max = paper.get((tr.experiment, tr.trial), (float("nan"), float("nan")))
        rows.append({"experiment": tr.experiment, "trial": tr.trial, "mode": tr.mode,
                     "integrated": round(tr.integrated, 2), "maximum": round(tr.maximum, 2),
                     "paper_integrated": p_int, "paper_maximum": p_max})
    return rows


def _cell(value: float) -> str:
    return "—" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{value:.2f}"


def table1_markdown(rows: list[dict]) -> str:
    """Table 1 as a markdown table, ours beside the paper's."""
    lines = ["| Exp (Env) | Trial | Integrated | Maximum | Paper integrated | Paper maximum |",
             "| --- | --- | ---: | ---: | ---: | ---: |"]
    for r in rows:
        label = r["trial"] if r["trial"] == "Control" else f"{r['trial']} ({r['mode']})"
        lines.append(f"| {r['experiment']} | {label} | {_cell(r['integrated'])} | {_cell(r['maximum'])} | "
                     f"{_cell(r['paper_integrated'])} | {_cell(r['paper_maximum'])} |")
    return "\n".join(lines)


def write_table1_csv(rows: list[dict], path: str | Path) -> None:
    """``table1.csv``: one row per trial; the paper's columns are empty where it has no value."""
    import csv

    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=TABLE1_COLUMNS)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: ("" if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()})


def write_table1_markdown(rows: list[dict], path: str | Path, title: str | None = None) -> None:
    text = table1_markdown(rows) + "\n"
    if title:
        text = f"{title}\n\n{text}"
    Path(path).write_text(text, encoding="utf-8")


# ----------------------------------------------------------------------- figures
#: How each kind of map feature is marked on the distance axis: colour, short label.
_MARKS = {"door": ("#a0522d", "door"), "opening": ("#d62728", "open door"), "crack": ("#222222", "crack"),
          "board": ("#e0a526", "board"), "recess": ("#7f7f7f", "recess"), "object": ("#9467bd", "object")}
_ROUTE = (0.0, 10.0)


def _pyplot():
    try:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("The figures need matplotlib: pip install matplotlib") from exc
    return plt


def _visible(features: list, kinds=None) -> list:
    """Features along the route that the sonar can hear (boards above the sonars are left out)."""
    out = []
    for f in features:
        if not (_ROUTE[0] - 0.5 <= f["position"] <= _ROUTE[1] + 0.5):
            continue
        if f["kind"] == "board" and "above the sonars" in f.get("description", ""):
            continue
        if f["id"].endswith("-frame"):
            continue  # the frame of an opened door: drawn with the opening
        out.append(f)
    return out


def _mark_features(ax, features: list, label: bool) -> None:
    """Shade each feature's extent on the distance axis; right-hand features solid, left hatched."""
    for f in _visible(features):
        colour, name = _MARKS.get(f["kind"], ("#7f7f7f", f["kind"]))
        half = max(float(f.get("width") or 0.0), 0.08) / 2
        lo, hi = f["position"] - half, f["position"] + half
        right = f.get("side") == "right"
        ax.axvspan(lo, hi, ymin=0, ymax=1, color=colour, alpha=0.10 if right else 0.05, lw=0)
        ax.axvspan(lo, hi, ymin=0, ymax=0.06, facecolor=colour if right else "none", edgecolor=colour,
                   hatch=None if right else "////", lw=0.6, alpha=0.9)
        if label:
            side = "R" if right else "L"
            ax.text(f["position"], 1.04, f"{name} {side}", transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=6.5, color=colour, rotation=0)


def _panel(ax, trial: Trial, top: bool, bottom: bool, ymax: float) -> None:
    _mark_features(ax, trial.features, label=top)
    ax.plot(trial.distance, trial.novelty, color="#1f3b73", lw=1.1, drawstyle="steps-mid")
    ax.axhline(trial.resting, color="0.35", ls="--", lw=0.8)
    ax.set_xlim(*_ROUTE)
    ax.set_ylim(0, 1.3 * ymax)  # headroom above 1.0 for the trial's label
    ax.set_yticks([0, ymax / 2, ymax])
    ax.tick_params(labelsize=7, length=2)
    ax.text(0.005, 0.97, trial.label, transform=ax.transAxes, ha="left", va="top", fontsize=8,
            fontweight="bold")
    ax.text(0.995, 0.97, f"integrated {trial.integrated:.2f}   max {trial.maximum:.2f}",
            transform=ax.transAxes, ha="right", va="top", fontsize=7)
    if not bottom:
        ax.tick_params(labelbottom=False)


def _columns(fig_title: str, columns: list[tuple[str, list[Trial]]], path, seed_note: str = ""):
    plt = _pyplot()
    rows = max(len(trials) for _, trials in columns)
    # inches: titles and feature names; axis label; each trial (smaller when A needed many pairs)
    top, bottom, panel = 0.85, 0.6, (1.0 if rows <= 8 else 0.6)
    height = top + bottom + panel * rows
    fig, axes = plt.subplots(rows, len(columns), figsize=(5.4 * len(columns), height), squeeze=False)
    fig.subplots_adjust(left=0.055, right=0.99, top=1 - top / height, bottom=bottom / height,
                        hspace=0.22, wspace=0.1)
    for c, (title, trials) in enumerate(columns):
        for r in range(rows):
            ax = axes[r, c]
            if r >= len(trials):
                ax.set_visible(False)
                continue
            _panel(ax, trials[r], top=(r == 0), bottom=(r == len(trials) - 1), ymax=1.0)
            if r == len(trials) - 1:
                ax.set_xlabel("distance along the route (m)", fontsize=8, labelpad=1)
            if c == 0:
                ax.set_ylabel("novelty", fontsize=7)
        axes[0, c].set_title(title, fontsize=9, pad=13)
    fig.suptitle(fig_title + seed_note, fontsize=10, y=1 - 0.08 / height, va="top")
    fig.text(0.5, 0.04 / height, "Shaded: the map's features (solid foot: right-hand wall, followed; "
             "hatched: left). Dashed: resting activity 0.0476.", ha="center", va="bottom", fontsize=7,
             color="0.3")
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)


def _of(trials: list[Trial], experiment: str) -> list[Trial]:
    return [t for t in trials if t.experiment == experiment]


def plot_experiment1(trials: list[Trial], path, note: str = "") -> Path:
    """The paper's figure 4: A's trials on the left, A*'s on the right."""
    return _columns("Experiment 1: output of the output neuron along the route",
                    [("A: learning (L) and non-learning (NL) runs", _of(trials, "A")),
                     ("A*: the door on the right at 3 m opened", _of(trials, "A*"))], path, note)


def plot_experiments2_3(trials: list[Trial], path, note: str = "") -> Path:
    """The paper's figure 5: B and its control on the left, C and its control on the right."""
    return _columns("Experiments 2 and 3: from the model learned in A; controls trained in the open area",
                    [("B: like A; door G (right, 3.6 m) inset deeper", _of(trials, "B")),
                     ("C: wider, brick and glass, deep doorway, boards", _of(trials, "C"))], path, note)


def write_figures(trials: list[Trial], folder, note: str = "") -> list[Path]:
    """Write ``figure4-experiment1.png`` and ``figure5-experiments2-3.png`` to ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return [plot_experiment1(trials, folder / "figure4-experiment1.png", note),
            plot_experiments2_3(trials, folder / "figure5-experiments2-3.png", note)]
