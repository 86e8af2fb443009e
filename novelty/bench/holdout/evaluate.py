"""What a hold-out cell computes: train on the familiar route, freeze, score the test part.

For a task whose scans are split into a training and a test part:

1. Training. An online detector streams the training scans, in order,
   ``train_passes`` times (``partial_fit``, novelty computed before each scan
   is learned, exactly as a robot repeating its route). A batch-only detector
   (``supports_online = False``) is ``fit`` once on the training scans.
   The test labels must be 0 or 1, both present (:mod:`novelty.io.tables.labels`);
   a score that is not finite, the detector's own raw score included, fails
   the cell with their count (a calibrated +inf reads as a constant).
2. Threshold. The training scans are scored without learning; the alarm
   threshold is their maximum (or the suite's quantile): see
   :func:`novelty.bench.holdout.metrics.training_threshold`. Nothing of the
   test part is used to set it.
3. Test. The test scans are scored without learning (``novelty(X)``) and the
   metrics of the table :data:`novelty.bench.holdout.metrics.METRICS`
   computed against the labels.
4. Route metrics (detection delay, false alarms, integrated novelty, the
   maximum), for a task whose scans lie along a route (:func:`has_route`);
   NaN for a table of scans in no order. False alarms: the alarms on a
   clean pass over the familiar route. That is
   the task's ``metadata["clean_test"]`` (a Dataset or an array of scans) if
   it has one, else the test runs that hold no novel scan (when others do),
   else the normal scans of the test part; the column
   ``false_alarm_source`` says which.
5. Places. For a task whose scans say whether the place of the object they
   see was seen while the detector learned (the objects tasks' column
   ``seen_place``): the ROC AUC of the objects in seen places and of those
   in unseen places, each against every normal test scan
   (:data:`PLACE_COLUMNS`).
6. Memory. Peak memory (``tracemalloc``) is measured by a second, identical run
   of steps 1 and 3, so that the tracer's overhead does not distort the times.

The novelty and label of every test scan are kept with the cell (its
arrays), for the plots and for the paired bootstrap over test scans.
"""

from __future__ import annotations

import threading
import time
import tracemalloc

import numpy as np

from ...io.tables.labels import check_both_classes, check_labels
from ..build import (check_finite, check_input_layout, check_raw_finite, load_task, make_detector, n_units, resting_novelty,
                     train_detector)
from ..specs import Cell
from . import metrics

__all__ = ["evaluate", "clean_pass", "has_route", "place_metrics", "METRIC_COLUMNS", "PLACE_COLUMNS",
           "MEASURED_COLUMNS"]

#: columns that depend only on the cell: identical across backends and reruns
#: (the task's sizes, the metrics of :data:`novelty.bench.holdout.metrics.METRICS`, the threshold and
#: what the detector became)
METRIC_COLUMNS = [
    "n_train", "n_test", "n_novel", "train_passes", "route", "task_split", *(m.column for m in metrics.METRICS),
    "threshold", "false_alarm_source", "resting_novelty", "n_units",
]
#: the columns a cell adds when its task says whether each object's place was seen (``seen_place``)
PLACE_COLUMNS = ["n_novel_seen", "roc_auc_seen", "n_novel_unseen", "roc_auc_unseen"]
#: columns measured on the machine (times, memory): they vary from run to run
MEASURED_COLUMNS = [
    "train_time_s", "score_time_s", "train_scans_per_s", "score_scans_per_s", "peak_memory_mb",
]

_TRACE_LOCK = threading.Lock()  # tracemalloc is process-wide: one traced run at a time


def clean_pass(data, test, y: np.ndarray) -> tuple[np.ndarray | None, str]:
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


def has_route(data) -> bool:
    """Whether the task's scans lie along a route, in order: what delay, false alarms and integrated novelty need.

    A task has a route when it says so (``metadata["route"]``), else when its
    scans carry a distance, a run or a time column. A table of scans drawn at
    random (a resampled benchmark file, arrays) has none.
    """
    if "route" in data.metadata:
        return bool(data.metadata["route"])
    return data.distance is not None or data.run is not None or "time" in data.columns


def evaluate(cell: Cell) -> tuple[dict, dict]:
    """The row of metrics and the per-scan arrays of a hold-out cell."""
    data = load_task(cell)
    train, test = data.train(), data.test()
    if test.y is None:
        raise ValueError(f"Task {cell.task.label!r} has no labels (y) for its test part.")
    if len(train) == 0 or len(test) == 0:
        raise ValueError(f"Task {cell.task.label!r} has an empty training or test part.")
    y = check_labels(test.y, f"Task {cell.task.label!r}: test labels").astype(bool)
    check_both_classes(y, f"Task {cell.task.label!r}")
    route = has_route(data)
    passes = data.train_passes

    det = make_detector(cell)
    check_input_layout(det, data, cell.task.label)
    start = time.perf_counter()
    train_detector(det, train.X, passes, train.columns.get("time"))
    train_time = time.perf_counter() - start
    start = time.perf_counter()
    novelty = np.asarray(det.novelty(test.X), dtype=np.float64)
    score_time = time.perf_counter() - start

    check_finite(novelty, "test scans")
    check_raw_finite(det, test.X, "test scans")
    train_novelty = np.asarray(det.novelty(train.X), dtype=np.float64)
    check_finite(train_novelty, "training scans")
    threshold = metrics.training_threshold(train_novelty, cell.threshold)
    clean, source = clean_pass(data, test, y)
    alarm_scores = np.asarray(det.novelty(clean), dtype=np.float64) if clean is not None else novelty[~y]
    check_finite(alarm_scores, "clean-pass scans")
    resting = resting_novelty(det)
    scored = metrics.compute(metrics.Scored(novelty, y, threshold, alarm_scores, resting))
    if not route:  # a delay or a count of alarms along no route means nothing
        scored.update({m.column: float("nan") for m in metrics.METRICS if m.route})
    row = {
        "n_train": len(train), "n_test": len(test), "n_novel": int(y.sum()), "train_passes": passes,
        "route": route, "task_split": data.metadata.get("split_description", ""),
        **scored,
        "threshold": threshold,
        "false_alarm_source": source,
        "resting_novelty": resting,
        "n_units": n_units(det),
        "train_time_s": train_time,
        "score_time_s": score_time,
        "train_scans_per_s": len(train) * (passes if getattr(det, "supports_online", True) else 1)
        / max(train_time, 1e-12),
        "score_scans_per_s": len(test) / max(score_time, 1e-12),
        "peak_memory_mb": _peak_memory(cell, train.X, passes, test.X) if cell.memory else float("nan"),
    }
    if "seen_place" in test.columns:
        row.update(place_metrics(novelty, y, test.columns["seen_place"]))
    distance = test.distance if test.distance is not None else np.arange(len(test), dtype=float)
    arrays = {"novelty": novelty, "y": y.astype(np.int8), "distance": np.asarray(distance, float),
              "threshold": np.float64(threshold), "resting": np.float64(resting)}
    if test.run is not None:
        arrays["run"] = np.asarray(test.run)
    return row, arrays


def place_metrics(novelty, y, seen_place) -> dict:
    """The ROC AUC and count of the novel scans whose object stands in a seen and in an unseen place, apart.

    ``seen_place``: per scan, whether the place of the object it sees was
    seen while the detector learned (:mod:`novelty.tasks.objects.places`);
    each class is scored against every normal test scan.
    """
    seen_place = np.asarray(seen_place, dtype=bool)
    row = {}
    for name, mask in (("seen", seen_place), ("unseen", ~seen_place)):
        row[f"n_novel_{name}"] = int(np.sum(y & mask))
        row[f"roc_auc_{name}"] = metrics.roc_auc_of(novelty, y, y & mask)
    return row


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
