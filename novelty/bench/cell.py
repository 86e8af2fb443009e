"""One benchmark cell: a detector on a task with a seed, evaluated by its protocol.

:func:`run_cell` is a pure function of the cell (detector spec, task spec,
seed, protocol): every backend (serial, joblib, Dask) calls it the same way
and gets the same numbers, apart from the measured times and memory. What it
computes is its protocol's ``evaluate`` (:func:`novelty.bench.protocol.get_protocol`:
:mod:`novelty.bench.holdout` or :mod:`novelty.bench.exploration`). Whatever
goes wrong inside a cell is caught and returned as a row with
``status = "error"``, so one failing cell never stops a run.
"""

from __future__ import annotations

import json
import traceback
import warnings
from typing import Any

from threadpoolctl import threadpool_limits

from .build import CellError, ensure_registered
from .definition import DEFINITION_COLUMN, TASK_DATA_COLUMN, definition_digest, task_digest
from .protocol import get_protocol
from .specs import Cell

__all__ = ["run_cell", "run_cell_in_worker", "failed_row", "cell_header", "record_warnings"]


def failed_row(cell: Cell, error: str) -> tuple[dict, dict]:
    """The row of a cell that failed outside :func:`run_cell` (a dead worker, a timeout)."""
    return {**cell_header(cell), "status": "error", "error": error, "warnings": "", "n_warnings": 0,
            "warning_types": ""}, {}


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
    """Run one cell; return its results row and its per-scan arrays (for plots and the bootstrap).

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
                ensure_registered(cell.components)
                task = row[TASK_DATA_COLUMN] = task_digest(cell)  # seeds of one world share it
                row[DEFINITION_COLUMN] = definition_digest(cell, task)  # what a resume checks its rows by
                values, arrays = get_protocol(cell.protocol).evaluate(cell)
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
    record_warnings(row, caught)
    return row, arrays


def record_warnings(row: dict, caught) -> None:
    """The warnings a cell raised, in its row: ``warnings`` (the first three distinct messages),
    ``n_warnings`` (how many were raised) and ``warning_types`` (their categories, sorted, comma-separated)."""
    messages = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))
    row["warnings"] = " | ".join(m[:200] for m in messages[:3])
    row["n_warnings"] = len(caught)
    row["warning_types"] = ",".join(sorted({w.category.__name__ for w in caught}))


def run_cell_in_worker(cell: Cell) -> tuple[dict, dict]:
    """:func:`run_cell` in a worker process or thread, where a ``KeyboardInterrupt`` is the cell's.

    In the bench's own process a ``KeyboardInterrupt`` is the user's and stops
    the run; raised in a worker it came from the cell (or reached the worker
    beside the bench, which stops the run itself), so the cell is recorded as
    failed, and run again by a resumed bench as every failed cell is.
    """
    try:
        return run_cell(cell)
    except KeyboardInterrupt:
        return failed_row(cell, "KeyboardInterrupt: raised inside the cell's worker")
