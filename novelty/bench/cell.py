"""One benchmark cell: train a detector on a task as the robot does, then score.

:func:`run_cell` is a pure function of the cell (detector spec, task spec,
seed): every backend (serial, joblib, Dask) calls it the same way and gets the
same numbers, apart from the measured times and memory. Whatever goes wrong
inside a cell is caught and returned as a row with ``status = "error"``, so one
failing cell never stops a run.

The procedure, for a task whose scans are split into a training and a test
part:

1. Training. An online detector streams the training scans, in order,
   ``train_passes`` times (``partial_fit``, novelty computed before each scan
   is learned, exactly as a robot repeating its route). A batch-only detector
   (``supports_online = False``) is ``fit`` once on the training scans.
2. Threshold. The training scans are scored without learning; the alarm
   threshold is their maximum (or the suite's quantile): see
   :func:`novelty.bench.metrics.training_threshold`. Nothing of the test part
   is used to set it.
3. Test. The test scans are scored without learning (``novelty(X)``) and the
   metrics of the table :data:`novelty.bench.metrics.METRICS` computed
   against the labels.
4. False alarms: the alarms on a clean pass over the familiar route. That is
   the task's ``metadata["clean_test"]`` (a Dataset or an array of scans) if
   it has one, else the test runs that hold no novel scan (when others do),
   else the normal scans of the test part; the column
   ``false_alarm_source`` says which.
5. Memory. Peak memory (``tracemalloc``) is measured by a second, identical run
   of steps 1 and 3, so that the tracer's overhead does not distort the times.

A suite with ``protocol = "exploration"`` runs
:func:`novelty.bench.prequential.evaluate_exploration` instead: every scan
scored, then learned, in order.
"""

from __future__ import annotations

import functools
import inspect
import json
import threading
import time
import traceback
import tracemalloc
import warnings
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from .._validation import pass_timestamps
from ..datasets import load, registry
from ..registry import detectors, of_kind
from . import metrics, river
from .prequential import evaluate_exploration
from .suite import Cell

__all__ = ["run_cell", "train_detector", "failed_row", "CellError", "METRIC_COLUMNS", "MEASURED_COLUMNS"]

#: columns that depend only on the cell: identical across backends and reruns
#: (the task's sizes, the metrics of :data:`novelty.bench.metrics.METRICS`, the threshold and
#: what the detector became)
METRIC_COLUMNS = [
    "n_train", "n_test", "n_novel", "train_passes", *(m.column for m in metrics.METRICS),
    "threshold", "false_alarm_source", "resting_novelty", "n_units",
]
#: columns measured on the machine (times, memory): they vary from run to run
MEASURED_COLUMNS = [
    "train_time_s", "score_time_s", "train_scans_per_s", "score_scans_per_s", "peak_memory_mb",
]

_TRACE_LOCK = threading.Lock()  # tracemalloc is process-wide: one traced run at a time


def _ensure_registered(components) -> None:
    """Register, in this (worker) process, the objects the parent resolved."""
    for kind, name, obj in components:
        registry = of_kind(kind)
        try:
            if name in registry and registry.get(name) is obj:
                continue
        except Exception:  # noqa: BLE001 - a broken entry is replaced below
            pass
        registry.register(name, obj, replace=True)


@functools.lru_cache(maxsize=16)  # a suite cycles through its seeds task by task
def _load_task_cached(name: str, options_json: str, seed: int):
    options = json.loads(options_json)
    valid = registry.parameters(name)
    if "seed" not in options and (valid is None or "seed" in valid):
        options["seed"] = seed
    return load(name, **options)


def load_task(cell: Cell):
    """The cell's task (cached per process: datasets are immutable)."""
    return _load_task_cached(cell.task.name, json.dumps(cell.task.options, sort_keys=True), cell.seed)


def make_detector(cell: Cell):
    """The cell's detector, seeded with the cell's seed unless the suite set one."""

    make = river.make if river.is_river(cell.detector.name) else detectors.make
    det = make(cell.detector.name, **cell.detector.params)
    if "random_state" not in cell.detector.params and hasattr(det, "get_params") \
            and "random_state" in det.get_params(deep=False):
        det.set_params(random_state=cell.seed)
    return det


def train_detector(det, X: np.ndarray, passes: int = 1, timestamps=None):
    """Train as the robot does: stream ``X`` ``passes`` times, or ``fit`` a batch-only detector.

    With ``timestamps`` (a task's time column), an online detector that takes
    them is given them; each further pass continues the clock, one typical
    step after the previous pass ended, as a robot driving the route again.
    """
    if not getattr(det, "supports_online", True):
        return det.fit(X)
    if timestamps is not None and "timestamps" not in inspect.signature(det.partial_fit).parameters:
        timestamps = None
    for k in range(passes):
        det.partial_fit(X, timestamps=None if timestamps is None else pass_timestamps(timestamps, k))
    return det


def _clean_pass(data, test, y: np.ndarray) -> tuple[np.ndarray | None, str]:
    """Scans of a clean pass over the familiar route, and where they come from.

    The task's ``metadata["clean_test"]`` (a Dataset or an array of scans)
    if it has one; else the test runs without any novel scan, when the test
    part has several runs and others do hold novelty; else ``None``.
    """
    clean = data.metadata.get("clean_test")
    if clean is not None:
        return np.asarray(getattr(clean, "X", clean), dtype=np.float64), "clean pass"
    if test.run is not None:
        runs = np.asarray(test.run)
        novel_runs = set(runs[y].tolist())
        clean_mask = ~np.isin(runs, list(novel_runs))
        if novel_runs and clean_mask.any():
            return test.X[clean_mask], "clean test runs"
    return None, "normal test scans"


def _resting(det) -> float:
    try:
        value = getattr(det, "resting_novelty", None)
    except Exception:  # noqa: BLE001 - a detector without a defined resting level
        value = None
    return 0.0 if value is None else float(value)


def _n_units(det) -> float:
    for owner in (getattr(det, "clusterer_", None), det):
        n = getattr(owner, "n_units_", None) if owner is not None else None
        if n is not None:
            return int(n)
    return float("nan")


def _evaluate(cell: Cell) -> tuple[dict, dict]:
    if cell.protocol == "exploration":
        return evaluate_exploration(cell, load_task(cell), functools.partial(make_detector, cell),
                                    _resting, _n_units)
    data = load_task(cell)
    train, test = data.train(), data.test()
    if test.y is None:
        raise ValueError(f"Task {cell.task.name!r} has no labels (y) for its test part.")
    if len(train) == 0 or len(test) == 0:
        raise ValueError(f"Task {cell.task.name!r} has an empty training or test part.")
    y = np.asarray(test.y).astype(bool)
    passes = data.train_passes

    det = make_detector(cell)
    start = time.perf_counter()
    train_detector(det, train.X, passes, train.columns.get("time"))
    train_time = time.perf_counter() - start
    start = time.perf_counter()
    novelty = np.asarray(det.novelty(test.X), dtype=np.float64)
    score_time = time.perf_counter() - start

    _check_finite(novelty, "test scans")
    train_novelty = np.asarray(det.novelty(train.X), dtype=np.float64)
    _check_finite(train_novelty, "training scans")
    threshold = metrics.training_threshold(train_novelty, cell.threshold)
    clean, source = _clean_pass(data, test, y)
    alarm_scores = np.asarray(det.novelty(clean), dtype=np.float64) if clean is not None else novelty[~y]
    _check_finite(alarm_scores, "clean-pass scans")
    resting = _resting(det)
    row = {
        "n_train": len(train), "n_test": len(test), "n_novel": int(y.sum()), "train_passes": passes,
        **metrics.compute(metrics.Scored(novelty, y, threshold, alarm_scores, resting)),
        "threshold": threshold,
        "false_alarm_source": source,
        "resting_novelty": resting,
        "n_units": _n_units(det),
        "train_time_s": train_time,
        "score_time_s": score_time,
        "train_scans_per_s": len(train) * (passes if getattr(det, "supports_online", True) else 1)
        / max(train_time, 1e-12),
        "score_scans_per_s": len(test) / max(score_time, 1e-12),
        "peak_memory_mb": _peak_memory(cell, train.X, passes, test.X) if cell.memory else float("nan"),
    }
    distance = test.distance if test.distance is not None else np.arange(len(test), dtype=float)
    arrays = {"novelty": novelty, "y": y.astype(np.int8), "distance": np.asarray(distance, float),
              "threshold": np.float64(threshold), "resting": np.float64(resting)}
    if test.run is not None:
        arrays["run"] = np.asarray(test.run)
    return row, arrays


def _check_finite(scores: np.ndarray, what: str) -> None:
    """A NaN or infinite score ranks nowhere: the cell fails rather than count on its other scans."""
    bad = int(np.count_nonzero(~np.isfinite(scores)))
    if bad:
        raise CellError(f"the detector scored {bad} of {scores.size} {what} NaN or infinite")


class CellError(ValueError):
    """A cell that ran but whose result cannot be used (reported without a source location)."""


def failed_row(cell: Cell, error: str) -> tuple[dict, dict]:
    """The row of a cell that failed outside :func:`run_cell` (a dead worker, a timeout)."""
    return {**cell_header(cell), "status": "error", "error": error, "warnings": ""}, {}


def _peak_memory(cell: Cell, X_train: np.ndarray, passes: int, X_test: np.ndarray) -> float:
    """Peak traced memory (MiB) of building, training and scoring the detector again."""
    with _TRACE_LOCK:
        was_tracing = tracemalloc.is_tracing()
        if not was_tracing:
            tracemalloc.start()
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        try:
            det = train_detector(make_detector(cell), X_train, passes)
            det.novelty(X_test)
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            if not was_tracing:
                tracemalloc.stop()
    return (peak - base) / 2**20


def cell_header(cell: Cell) -> dict:
    """The columns that name a cell (written for failed cells too)."""
    return {
        "cell_id": cell.id,
        "detector": cell.detector.label,
        "detector_name": cell.detector.name,
        "params": json.dumps(cell.detector.params, sort_keys=True, default=str),
        "task": cell.task.label,
        "task_name": cell.task.name,
        "task_options": json.dumps(cell.task.options, sort_keys=True, default=str),
        "seed": cell.seed,
        "threshold_rule": cell.threshold,
    }


def run_cell(cell: Cell) -> tuple[dict, dict]:
    """Run one cell; return its results row and its per-scan arrays (for plots).

    Never raises for a failure inside the cell (any exception, ``SystemExit``
    included; ``KeyboardInterrupt`` stops the run): the row then has
    ``status = "error"`` and ``error`` (the exception, one line), and the
    arrays are empty. A cell whose scores include NaN or infinity fails.
    """
    row: dict[str, Any] = cell_header(cell)
    arrays: dict = {}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            # One BLAS thread per cell: same arithmetic in every backend, no oversubscription.
            with threadpool_limits(1):
                _ensure_registered(cell.components)
                values, arrays = _evaluate(cell)
            row.update(values)
            row["status"], row["error"] = "ok", ""
        except KeyboardInterrupt:
            raise
        except BaseException as exc:  # noqa: BLE001 - a failing cell is a result, not a crash
            frame = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
            where = (f" (at {frame.filename.rsplit('/', 1)[-1]}:{frame.lineno})"
                     if frame and not isinstance(exc, CellError) else "")
            message = " ".join(str(exc).split())
            row["status"], row["error"] = "error", f"{type(exc).__name__}: {message}{where}"
    messages = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))
    row["warnings"] = " | ".join(m[:200] for m in messages[:3])
    return row, arrays
