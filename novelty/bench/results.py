"""Results on disk: ``results.jsonl`` (the record), ``results.csv``, per-cell arrays.

``results.jsonl`` is appended one line per finished cell, flushed at once, so
an interrupted run loses at most the cells that were running; it is the resume
record. A cell whose ``cell_id`` is there with ``status = "ok"`` is not run
again, unless its row's ``definition`` differs from what the cell resolves to
now (:mod:`novelty.bench.definition`); a failed cell is run again (its new
line supersedes the old one).
``results.csv`` is rewritten from it after every run, its rows in a canonical
order (detector, task, seed, threshold rule, cell id) and its columns in
their order of first appearance down those rows, so that the files of one
suite run serially, with joblib or on Dask are equal byte for byte apart
from the columns of :data:`MACHINE_COLUMNS` (times, speeds, traced memory and
the time a cell finished; every metric is the same on every backend). The
novelty of every test scan of a cell goes to ``cells/<cell_id>.npz`` for the
plots.

One run at a time writes to a folder: a run holds ``.lock`` (an advisory
``flock``, released by the system when the process ends, however it ends;
the file names the holder's pid) and a second run into the same folder
refuses to start (:class:`OutputBusyError`) rather than compute every cell
twice. Files are written under unique temporary names and renamed into
place, so a reader never sees a part of one.
"""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import platform
import subprocess
import sys
from datetime import datetime, timezone
from importlib import metadata as importlib_metadata
from importlib import resources
from pathlib import Path
from typing import Iterable

import numpy as np

from .._atomic import write_atomically
from .._version import __version__

__all__ = ["ResultsStore", "OutputBusyError", "provenance", "read_rows", "canonical_order", "RESULTS_JSONL",
           "RESULTS_CSV", "MACHINE_COLUMNS"]

RESULTS_JSONL = "results.jsonl"
RESULTS_CSV = "results.csv"
#: the columns of results.csv that measure the machine and the moment, not the detector: they differ
#: from run to run and from backend to backend (every other column is the same)
MACHINE_COLUMNS = ("train_time_s", "score_time_s", "train_scans_per_s", "score_scans_per_s", "peak_memory_mb",
                   "finished_at")
_VERSIONED = ("novelty", "numpy", "scipy", "scikit-learn", "numba", "joblib", "dask", "distributed")


def _version(dist: str) -> str | None:
    if dist == "novelty":  # this package, whatever its distribution is named (the index's "novelty" is not it)
        return __version__
    try:
        return importlib_metadata.version(dist)
    except importlib_metadata.PackageNotFoundError:
        return None


#: the source tree of a checkout (a non-editable install has no .git there)
_SOURCE_ROOT = Path(__file__).resolve().parents[2]
#: written into the installed package by the build (setup.py), beside ``novelty/__init__.py``
BUILD_REVISION_FILE = "_revision.txt"


def git_revision() -> str:
    """The git commit of the novelty code that runs (``+dirty`` if modified), or ``"unknown"``.

    From a checkout (an editable install, or ``PYTHONPATH``), git is asked;
    an installed package carries the revision its build recorded; a package
    built from a source archive without git history says ``"unknown"``.
    """
    return _checkout_revision(_SOURCE_ROOT) or _built_revision() or "unknown"


def _checkout_revision(root: Path) -> str | None:
    if not (root / ".git").exists():
        return None
    try:
        rev = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True,
                             text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return rev + ("+dirty" if dirty else "") if rev else None


def _built_revision() -> str | None:
    try:
        text = resources.files("novelty").joinpath(BUILD_REVISION_FILE).read_text(encoding="utf-8")
    except (OSError, ModuleNotFoundError):
        return None
    return text.strip() or None


def provenance() -> dict:
    """Columns recording where a row came from: versions, git revision, machine, time."""
    versions = {name: v for name in _VERSIONED if (v := _version(name)) is not None}
    versions["python"] = platform.python_version()
    return {
        "versions": json.dumps(versions, sort_keys=True),
        "git_revision": git_revision(),
        "host": platform.node(),
        "platform": f"{sys.platform}-{platform.machine()}",
        "finished_at": datetime.now(timezone.utc).isoformat(timespec="seconds"),
    }


def _jsonable(value):
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        value = float(value)
        return None if math.isnan(value) else value
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def read_rows(path) -> list[dict]:
    """Rows of a ``results.jsonl`` (later rows of the same cell win; torn lines skipped)."""
    path = Path(path)
    if path.is_dir():
        path = path / RESULTS_JSONL
    rows: dict[str, dict] = {}
    if not path.exists():
        return []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            line = line.strip()
            if not line:
                continue
            try:
                row = json.loads(line)
            except ValueError:  # the last line of an interrupted run
                continue
            if isinstance(row, dict) and "cell_id" in row:
                rows.pop(row["cell_id"], None)
                rows[row["cell_id"]] = row
    return list(rows.values())


def canonical_order(rows: Iterable[dict]) -> list[dict]:
    """``rows`` sorted by detector, task, seed, threshold rule and cell id: the order of results.csv,
    whatever order the cells finished in."""
    def key(row: dict) -> tuple:
        seed = row.get("seed")
        return (str(row.get("detector", "")), str(row.get("task", "")),
                (0, seed, "") if isinstance(seed, int) else (1, 0, str(seed)),
                str(row.get("threshold_rule", "")), str(row.get("cell_id", "")))

    return sorted(rows, key=key)


class OutputBusyError(OSError):
    """Another run is writing to the same output folder."""


class ResultsStore:
    """The output folder of a benchmark run."""

    def __init__(self, out):
        self.out = Path(out)
        self.jsonl = self.out / RESULTS_JSONL
        self.csv = self.out / RESULTS_CSV
        self.cells_dir = self.out / "cells"

    def prepare(self) -> None:
        if self.out.exists() and not self.out.is_dir():
            raise FileExistsError(f"--out {self.out} exists and is not a folder.")
        self.cells_dir.mkdir(parents=True, exist_ok=True)

    @contextlib.contextmanager
    def lock(self):
        """Hold the folder for this run; :class:`OutputBusyError` if another run holds it."""
        try:
            # POSIX only: elsewhere the folder is not locked
            import fcntl
        except ImportError:  # not POSIX: no lock
            yield
            return
        path = self.out / ".lock"
        with open(path, "a+", encoding="utf-8") as fh:
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                fh.seek(0)
                holder = fh.read().strip() or "unknown"
                raise OutputBusyError(
                    f"Another novelty bench (pid {holder}) is writing to {self.out}; wait for it "
                    "to finish, or give another --out."
                ) from None
            fh.seek(0)
            fh.truncate()
            fh.write(f"{os.getpid()}\n")
            fh.flush()
            try:
                yield
            finally:
                fh.seek(0)
                fh.truncate()
                fcntl.flock(fh, fcntl.LOCK_UN)

    def rows(self) -> list[dict]:
        return read_rows(self.jsonl)

    def finished(self) -> dict[str, dict]:
        """The rows of the cells that finished without error, by cell id."""
        return {r["cell_id"]: r for r in self.rows() if r.get("status") == "ok"}

    def append(self, row: dict, arrays: dict | None = None) -> None:
        if arrays:
            write_atomically(self.cells_dir / f"{row['cell_id']}.npz", lambda fh: np.savez(fh, **arrays))
        torn = self._ends_torn()
        with open(self.jsonl, "a", encoding="utf-8") as fh:
            if torn:  # an interrupted write: keep the new row on a line of its own
                fh.write("\n")
            fh.write(json.dumps({k: _jsonable(v) for k, v in row.items()}, default=str) + "\n")
            fh.flush()
            os.fsync(fh.fileno())

    def _ends_torn(self) -> bool:
        if not self.jsonl.exists() or self.jsonl.stat().st_size == 0:
            return False
        with open(self.jsonl, "rb") as fh:
            fh.seek(-1, os.SEEK_END)
            return fh.read(1) != b"\n"

    def arrays(self, cell_id: str) -> dict | None:
        path = self.cells_dir / f"{cell_id}.npz"
        if not path.exists():
            return None
        with np.load(path, allow_pickle=False) as npz:
            return {k: npz[k] for k in npz.files}

    def write_csv(self, rows: Iterable[dict] | None = None) -> Path:
        rows = canonical_order(self.rows() if rows is None else rows)
        columns: list[str] = []
        for row in rows:
            columns.extend(k for k in row if k not in columns)

        def write(fh) -> None:
            writer = csv.DictWriter(fh, fieldnames=columns, restval="")
            writer.writeheader()
            for row in rows:
                writer.writerow({k: "" if v is None else v for k, v in row.items()})

        return write_atomically(self.csv, write, text=True)
