"""Benchmarking from Python: :func:`run` detectors on tasks, get a :class:`Results`.

>>> import numpy as np
>>> from novelty import bench
>>> rng = np.random.default_rng(0)
>>> X_train, X_test = rng.random((200, 8)), rng.random((100, 8))
>>> X_test[:20] += 0.8                                  # twenty novel scans
>>> y_test = np.r_[np.ones(20), np.zeros(80)]
>>> results = bench.run(["kmeans-stanley", "parzen"], {"mine": (X_train, X_test, y_test)})
>>> results.tasks, len(results.rows)
(['mine'], 2)

Detectors are registry names (with parameters, ``"hsom n_rows=5"``),
detector objects (each cell runs an unfitted copy), or a dict
``{label: either}``. Tasks are registered names (``"inspection-easy"``,
``"files path=scans.csv name=lab"``), task objects (a
:class:`~novelty.datasets.Dataset` with a train/test split: an exploration
from :func:`novelty.exploration.from_runs`, a recording, one you built), a
tuple ``(X_train, X_test, y_test)``, or a dict ``{name: any of these}``.
Nothing needs registering. With ``out``, the run writes what ``novelty bench``
writes (``results.csv``, ``results.jsonl``, ``summary.md``, ``plots/``) and
resumes there; without it the files go to a temporary folder.

The command line ``novelty bench`` builds a :class:`~novelty.bench.suite.Suite`
and calls :func:`run_suite`, as :func:`run` does.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import tempfile
import weakref
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ..baselines.wrapping import as_detector
from ..data import Dataset
from ..io.tables.labels import check_both_classes, check_labels
from ..datasets.resampling import ResampledTask
from .compare import compare_on_task, comparison_text
from .protocol import get_protocol
from .reports.statistics import paired_text, statistics_line
from .results import ResultsStore
from .runner import BenchReport, run_bench
from .specs import DetectorSpec, SuiteError, TaskSpec, detector_from_text, parse_seeds, tasks_from_text
from .stats import across_tasks
from .stats.aggregate import TaskTable, task_table
from .suite import Suite

__all__ = ["run", "run_suite", "Results"]


@dataclass
class Results:
    """What a benchmark run measured.

    Attributes
    ----------
    rows : list of dict
        One row a cell (detector, task, seed): its metrics, times, status.
    protocol : str
    out : Path
        Where the files are (a temporary folder when :func:`run` had no ``out``).
    report : BenchReport
        The run's record (files written, notes, failed cells).
    """

    rows: list[dict]
    protocol: str
    out: Path
    report: BenchReport
    reference: str | None = None
    _keep: Any = field(default=None, repr=False)  # a temporary folder, kept while the results live

    @property
    def tasks(self) -> list[str]:
        """The tasks, by name, in the order they ran."""
        return list(dict.fromkeys(r["task"] for r in self.rows))

    @property
    def per_task(self) -> TaskTable:
        """The protocol's metric per detector and task: the mean over seeds, its interval, repeated seeds."""
        return task_table(self.rows, get_protocol(self.protocol).metric)

    @property
    def statistics(self) -> dict:
        """The tests over tasks: ``friedman`` (or None), ``pairwise`` (Wilcoxon-Holm), ``line`` (in words)."""
        table = self.per_task
        return {"friedman": across_tasks.friedman(table), "pairwise": across_tasks.pairwise_wilcoxon(table),
                "line": statistics_line(self.rows)}

    @property
    def table(self) -> str:
        """The protocol's table and the paired comparison, as ``novelty bench`` prints them."""
        return self.report.table

    @property
    def summary(self) -> str:
        """The text of ``summary.md``."""
        return (self.out / "summary.md").read_text(encoding="utf-8")

    def paired(self, reference: str | None = None) -> str:
        """Each detector against ``reference`` over tasks, as a table."""
        return paired_text(self.rows, reference or self.reference)

    def compare_on_task(self, task: str, reference: str | None = None, resamples: int = 2000,
                        seed: int = 0) -> list[dict]:
        """Each detector against ``reference`` on one task: paired bootstrap (and corrected t over seeds);
        on an exploration task, the mean difference over the seeds' worlds and its interval."""
        return compare_on_task(self.rows, ResultsStore(self.out).arrays, task, reference or self.reference,
                               resamples, seed)

    def comparison_text(self, task: str, reference: str | None = None, **options) -> str:
        """:meth:`compare_on_task` as a table."""
        return comparison_text(self.compare_on_task(task, reference, **options))

    def to_frame(self):
        """The rows as a ``pandas.DataFrame`` (pandas is optional: ``pip install pandas``)."""
        try:
            import pandas  # optional dependency, imported only for a data frame
        except ImportError:
            raise ImportError("Results.to_frame() needs pandas (pip install pandas); the rows are in "
                              "Results.rows as dicts.") from None
        return pandas.DataFrame(self.rows)


# ------------------------------------------------------------ what to run
def _detector_spec(label: str | None, item) -> DetectorSpec:
    if isinstance(item, DetectorSpec):
        return item
    if isinstance(item, str):
        spec = detector_from_text(item)
        return DetectorSpec(spec.name, spec.params, label or spec.label)
    if hasattr(item, "get_params") and hasattr(item, "fit"):
        try:  # a scikit-learn or PyOD outlier detector is taken as it is
            det = as_detector(item)
        except TypeError as exc:
            raise SuiteError(str(exc)) from None
        name = label or type(item).__name__
        params = json.loads(json.dumps(det.get_params(deep=False), sort_keys=True, default=str))
        return DetectorSpec(name, params, name, instance=det)
    raise SuiteError(f"A detector must be a registry name, a detector object (ours, scikit-learn's or PyOD's) "
                     f"or a DetectorSpec; got {item!r}.")


def detector_specs(detectors) -> list[DetectorSpec]:
    """Detector specs from names, objects, specs, or a dict ``{label: any of these}``."""
    if isinstance(detectors, (str, DetectorSpec)) or hasattr(detectors, "fit"):
        detectors = [detectors]
    items = detectors.items() if isinstance(detectors, Mapping) else [(None, d) for d in detectors]
    return [_detector_spec(label, item) for label, item in items]


def _fingerprint(data: Dataset) -> str:
    """A short hash of a task object's scans, labels and split: its cells' ids change with its data."""
    digest = hashlib.sha256()
    for part in (data.X, data.y, data.split, data.run):
        if part is not None:
            digest.update(np.ascontiguousarray(part).tobytes())
    return digest.hexdigest()[:16]


def _from_arrays(name: str, arrays: Sequence) -> Dataset:
    if len(arrays) != 3:
        raise SuiteError(f"Task {name!r}: a tuple task is (X_train, X_test, y_test); got {len(arrays)} items.")
    X_train, X_test = (np.asarray(a, dtype=np.float64) for a in arrays[:2])
    try:
        y_test = check_labels(arrays[2], f"Task {name!r}: y_test")
    except ValueError as exc:
        raise SuiteError(str(exc)) from None
    if X_train.ndim != 2 or X_test.ndim != 2 or X_train.shape[1] != X_test.shape[1]:
        raise SuiteError(f"Task {name!r}: X_train and X_test must be 2-D with the same columns; got "
                         f"{X_train.shape} and {X_test.shape}.")
    if y_test.shape != (len(X_test),):
        raise SuiteError(f"Task {name!r}: y_test needs one label a test scan; got shape {y_test.shape}.")
    X = np.vstack([X_train, X_test])
    y = np.r_[np.zeros(len(X_train)), y_test].astype(np.int64)
    return Dataset(name, X, y=y, split=np.r_[np.full(len(X_train), "train"), np.full(len(X_test), "test")])


def _checked_task(label: str, data: Dataset) -> None:
    """A task object's test labels: 0/1, both classes (a hold-out verdict needs them)."""
    if data.split is None or data.y is None:
        return  # an exploration task, or one the protocol refuses with its own words
    try:
        y = check_labels(data.y[data.split == "test"], f"Task {label!r}: test labels")
        check_both_classes(y, f"Task {label!r}")
    except ValueError as exc:
        raise SuiteError(str(exc)) from None


def _task_spec(name: str | None, item) -> list[TaskSpec]:
    if isinstance(item, TaskSpec):
        return [item]
    if isinstance(item, str):
        specs = tasks_from_text(item)
        if name is not None and len(specs) == 1:
            specs = [TaskSpec(specs[0].name, specs[0].options, name)]
        return specs
    if isinstance(item, ResampledTask):
        label = name or item.name
        options = {"fingerprint": _fingerprint(Dataset(label, item.X, y=item.y)), **item.protocol.as_options()}
        return [TaskSpec(label, options, label, data=item)]
    if isinstance(item, tuple):
        item = _from_arrays(name or "arrays", item)
    if isinstance(item, Dataset):
        label = name or item.name
        if "exploration" not in item.metadata:  # exploration tasks are scored by encounters, not test labels
            _checked_task(label, item)
        return [TaskSpec(label, {"fingerprint": _fingerprint(item)}, label, data=item)]
    raise SuiteError(f"A task must be a registered name, a Dataset, a resampled table "
                     f"(novelty.datasets.resampled), a tuple (X_train, X_test, y_test) or a TaskSpec; "
                     f"got {type(item).__name__}.")


def task_specs(tasks) -> list[TaskSpec]:
    """Task specs from names, task objects, tuples of arrays, specs, or a dict ``{name: any of these}``.

    A ``files`` task whose ``path`` is a folder is one task a data file in it.
    """
    if isinstance(tasks, (str, TaskSpec, Dataset, ResampledTask)):
        tasks = [tasks]
    items = tasks.items() if isinstance(tasks, Mapping) else [(None, t) for t in tasks]
    return [spec for name, item in items for spec in _task_spec(name, item)]


class _Scratch:
    """A temporary folder, removed when the last reference to it goes or at exit, without the
    ResourceWarning a ``TemporaryDirectory`` left to the garbage collector gives."""

    def __init__(self):
        self.name = tempfile.mkdtemp(prefix="novelty-bench-")
        self._remove = weakref.finalize(self, shutil.rmtree, self.name, ignore_errors=True)


# ------------------------------------------------------------------- runs
def run_suite(suite: Suite, out=None, backend: str = "serial", jobs: int = 1, plots: bool = True,
              quiet: bool = True, **options) -> Results:
    """Run a checked :class:`~novelty.bench.suite.Suite` into ``out`` (a temporary folder if None)."""
    keep = None
    if out is None:
        keep = _Scratch()
        out, plots = keep.name, False
    report = run_bench(suite, out, backend=backend, jobs=jobs, plots=plots, quiet=quiet, **options)
    return Results(report.rows, suite.protocol, Path(out), report, suite.reference_label, keep)


def run(detectors, tasks, seeds=1, protocol: str = "holdout", backend: str = "serial", jobs: int = 1,
        out=None, reference: str | None = None, threshold="max", memory: bool = False,
        plots: bool = True, quiet: bool = True) -> Results:
    """Benchmark ``detectors`` on ``tasks`` over ``seeds`` and return the :class:`Results`.

    Parameters
    ----------
    detectors : str, detector, DetectorSpec, or a list or dict of them
        Registry names (with parameters, ``"hsom n_rows=5"``) or detector objects.
    tasks : str, Dataset, tuple, TaskSpec, or a list or dict of them
        Registered tasks, task objects (``from_runs``, a recording, your own
        :class:`~novelty.datasets.Dataset`), or ``(X_train, X_test, y_test)``.
    seeds : int or list of int, default=1
        A count (seeds 0 to n-1) or the seeds. A task object is the same
        data for every seed; a detector gets the seed as ``random_state``.
    protocol : {"holdout", "exploration"}, default="holdout"
    backend : {"serial", "joblib", "dask"}, default="serial"
    jobs : int, default=1
    out : path, optional
        Write the files and plots of ``novelty bench`` there (and resume).
    reference : str, optional
        The label of the detector the others are paired with (default: the first detector).
    threshold : "max" or float, default="max"
        The alarm threshold rule (``max`` of the training novelty, or a quantile).
    memory : bool, default=False
        Measure peak memory (a second, traced run of each cell).
    plots : bool, default=True
        Draw the plots (with ``out`` only).
    quiet : bool, default=True
        No progress output.

    Raises
    ------
    KeyboardInterrupt
        Interrupted (Ctrl-C; with the serial backend, also a ``KeyboardInterrupt``
        raised inside a cell, which runs in this process): after the finished
        cells are written to ``out``, which a second call resumes.
    """
    suite = Suite(detector_specs(detectors), task_specs(tasks), parse_seeds(seeds), name="python",
                  threshold=threshold, memory=memory, reference=reference, protocol=protocol)
    results = run_suite(suite.check(), out, backend=backend, jobs=jobs, plots=plots, quiet=quiet)
    if results.report.interrupted:   # the caller's Ctrl-C stops the caller too, as anywhere in Python
        kept = (f"their rows are in {out}; run again with the same out= to resume" if out is not None
                else "give out= to keep the finished cells and resume")
        raise KeyboardInterrupt(f"novelty.bench.run was interrupted after {results.report.ran} cells ({kept}).")
    return results
