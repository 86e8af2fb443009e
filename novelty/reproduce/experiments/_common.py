"""What every experiment shares: its result, corridor A's six trials, tables, a process pool."""

from __future__ import annotations

import csv
import functools
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

import numpy as np

import novelty
from novelty._children import isolated_children
from novelty._progress import Steps
from novelty.reproduce.figures import pyplot  # noqa: F401  (the experiments' figures)
from novelty.sonar import simulate

#: Table 1's A column (Marsland et al. 2000): integrated output of trials 1-6.
PAPER_A = (9.17, 2.64, 1.34, 1.07, 0.52, 0.30)
#: The six trials of A: learning (L) and non-learning (NL) runs in turn.
A_MODES = ("L", "NL", "L", "NL", "L", "NL")


@dataclass
class Result:
    """What an experiment found: a table (rows of equal keys), findings in words, a figure."""

    name: str
    title: str
    rows: list[dict]
    findings: list[str] = field(default_factory=list)
    figure: Path | None = None
    note: str = ""
    tables: dict[str, list[dict]] = field(default_factory=dict)

    def markdown(self) -> str:
        """The table as markdown, then the note and the findings as a list."""
        text = [markdown_table(self.rows)]
        if self.note:
            text.append(self.note)
        if self.findings:
            text.append("\n".join(f"- {line}" for line in self.findings))
        return "\n\n".join(text) + "\n"

    def blocks(self) -> dict[str, str]:
        """Markdown by key, for the report: ``NAME`` and ``NAME-TABLE`` for each further table."""
        out = {self.name: self.markdown()}
        out.update({f"{self.name}-{key}": markdown_table(rows) + "\n" for key, rows in self.tables.items()})
        return out

    def write(self, folder: Path) -> list[Path]:
        """``NAME.csv``, ``NAME.md`` and a CSV per further table in ``folder`` (the figure is there)."""
        folder.mkdir(parents=True, exist_ok=True)
        written = [write_csv(self.rows, folder / f"{self.name}.csv")]
        written += [write_csv(rows, folder / f"{self.name}-{key}.csv") for key, rows in self.tables.items()]
        md_path = folder / f"{self.name}.md"
        md_path.write_text(f"## {self.title}\n\n" + "\n".join(self.blocks().values()), encoding="utf-8")
        return written + [md_path] + ([self.figure] if self.figure else [])


def write_csv(rows: list[dict], path: Path) -> Path:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return path


def _cell(value) -> str:
    if isinstance(value, (float, np.floating)):
        return f"{value:.2f}"
    return str(value)


def markdown_table(rows: list[dict]) -> str:
    keys = list(rows[0])
    numeric = [isinstance(rows[0][k], (int, float, np.number)) and not isinstance(rows[0][k], bool)
               for k in keys]
    lines = ["| " + " | ".join(keys) + " |",
             "| " + " | ".join("---:" if n else "---" for n in numeric) + " |"]
    lines += ["| " + " | ".join(_cell(r[k]) for k in keys) + " |" for r in rows]
    return "\n".join(lines)


# ---------------------------------------------------------------- corridor A
@functools.lru_cache(maxsize=256)
def traversal(environment, seed: int, run: int, options: tuple = ()) -> np.ndarray:
    """The scans of one simulated run (cached: experiments share runs)."""
    return simulate(environment, seed=seed, first_run=run, **dict(options)).X


def span(seeds) -> str:
    """``"0-9"`` for ``range(10)``."""
    seeds = list(seeds)
    return f"{seeds[0]}-{seeds[-1]}" if len(seeds) > 1 else str(seeds[0])


def mean_trials(found: list[dict]) -> np.ndarray:
    """Mean integrated novelty of each of the six trials over the seeds' results."""
    return np.mean([f["integrated"] for f in found], axis=0)


def trial_columns(integrated) -> dict:
    return {f"trial {t + 1}": float(integrated[t]) for t in range(len(A_MODES))}


def plot_trials(rows: list[dict], key: str, path: Path, title: str, highlight: str | None = None) -> Path:
    """Mean integrated novelty of each trial, one line per row, beside the paper's A (log scale)."""
    plt = pyplot()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    trials = np.arange(1, len(A_MODES) + 1)
    for row in rows:
        ax.plot(trials, [max(row[f"trial {t}"], 1e-3) for t in trials], marker="o", label=row[key],
                lw=2 if row[key] == highlight else 1)
    ax.plot(trials, PAPER_A, "k--", marker="s", label="paper, A (Table 1)")
    ax.set_yscale("log")
    ax.set_xlabel("trial (odd: learning, even: not learning)")
    ax.set_ylabel("integrated novelty (log; 0 drawn at 0.001)")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=6.5, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def learn_counting_winners(det, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Learn ``X`` scan by scan as ``det.stream`` does; return novelty and each scan's winner."""
    novelty_, winners = np.empty(len(X)), np.empty(len(X), dtype=np.intp)
    start = 0
    if not hasattr(det, "n_features_in_"):
        novelty_[0] = det.stream(X[:1])[0]
        # a fresh map: the first winner is the one unit that fell by a winner's step
        winners[0] = int(np.argmin(det.synapse_.efficacy_))
        start = 1
    for i in range(start, len(X)):
        winners[i] = det.winners(X[i:i + 1])[0][0]
        novelty_[i] = det.score_learn_one(X[i])
    return novelty_, winners


def six_trials(seed: int, params: dict | None = None, environment="a", options: tuple = (),
               runs=None) -> dict:
    """A's six trials (L, NL, L, NL, L, NL) with the paper's protocol from an untrained filter.

    ``runs`` gives the scans of each trial (default: the simulated runs 0-5
    of ``environment`` under ``seed`` and simulator ``options``). Returns
    the integrated novelty of each trial, the distinct winners of each,
    and the wins of every unit over the learning trials.
    """
    det = novelty.make("hsom", random_state=seed, **(params or {}))
    integrated, distinct, learned = [], [], []
    for k, mode in enumerate(A_MODES):
        X = runs[k] if runs is not None else traversal(environment, seed, k, options)
        if mode == "L":
            nov, won = learn_counting_winners(det, X)
            learned.append(won)
        else:
            nov, (won, _) = det.novelty(X), det.winners(X)
        above = nov - det.resting_novelty
        integrated.append(float(above.sum()))
        distinct.append(int(np.unique(won).size))
    wins = np.bincount(np.concatenate(learned), minlength=det.clusterer_.n_units_)
    # the last trial's novelty that units which won at most twice while learning gave
    rare_share = float(above[wins[won] <= 2].sum() / above.sum()) if above.sum() > 0 else float("nan")
    return {"integrated": integrated, "distinct": distinct, "rare_share": rare_share,
            "learning_winners": int(np.sum(wins > 0))}


# ---------------------------------------------------------------- processes
#: (experiment name, stream) while an experiment reports its progress (:func:`reporting`)
_PROGRESS: ContextVar[tuple[str, TextIO] | None] = ContextVar("progress", default=None)


@contextmanager
def reporting(name: str, stream: TextIO | None):
    """Within the block, :func:`parallel` reports each finished step of experiment ``name`` to ``stream``."""
    token = _PROGRESS.set(None if stream is None else (name, stream))
    try:
        yield
    finally:
        _PROGRESS.reset(token)


def parallel(function, items, jobs: int) -> list:
    """``[function(item) for item in items]``, in ``jobs`` processes when more than one.

    Every result depends on its item alone (seeded), so the answer is the
    same in any number of processes. Inside :func:`reporting`, each finished
    item is a step reported (an experiment's steps take seconds each).
    """
    items = list(items)
    progress = _PROGRESS.get()
    if progress is None:
        return _results(function, items, jobs, lambda: None)
    with Steps(progress[0], len(items), progress[1]) as steps:
        return _results(function, items, jobs, steps.step)


def _results(function, items: list, jobs: int, done) -> list:
    results = []
    if jobs <= 1 or len(items) <= 1:
        for item in items:
            results.append(function(item))
            done()
        return results
    # spawn, not fork: numba may be compiling in a background thread of this process
    with isolated_children(), ProcessPoolExecutor(max_workers=jobs,
                                                  mp_context=multiprocessing.get_context("spawn")) as pool:
        for result in pool.map(function, items):
            results.append(result)
            done()
    return results
