"""What the commands share: the parser, user errors, parameters, scan files."""

from __future__ import annotations

import argparse
import csv
import io
import sys
from pathlib import Path
from typing import Any, Sequence

import numpy as np

__all__ = ["NoveltyParser", "UserError", "one_line", "user_errors", "parse_params", "read_scans",
           "write_novelty", "add_command"]


class UserError(Exception):
    """Something the user can fix (a file, a name, a value): one line, exit code 2."""


def one_line(exc: BaseException) -> str:
    text = str(exc.args[0]) if isinstance(exc, KeyError) and exc.args else str(exc)
    text = " ".join(text.split())
    return text or type(exc).__name__


def user_errors() -> tuple[type[BaseException], ...]:
    """Exceptions that mean the input was wrong, not the program."""
    from ..bench.backends import BackendError
    from ..bench.suite import SuiteError
    from ..persistence import ModelFileError
    from ..registry import RegistryError

    return (UserError, SuiteError, RegistryError, ModelFileError, BackendError, OSError, ValueError)


class NoveltyParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line (and exit code 2)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def add_command(subparsers, name: str, summary: str, description: str, examples: Sequence[str]):
    """A sub-command parser with a description and an examples section in --help."""
    epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples)
    return subparsers.add_parser(name, help=summary, description=description, epilog=epilog)


def parse_params(items: Sequence[str] | None) -> dict[str, Any]:
    """``["k=v", ...]`` to a dict with JSON-ish values (``5``, ``1.2``, ``true``, ``som``)."""
    from ..bench.suite import SuiteError, parse_assignments

    try:
        return parse_assignments(items or [])
    except SuiteError as exc:
        raise UserError(str(exc)) from None


# ----------------------------------------------------------------- scan files
#: columns of a scan file that are not sensors
META_COLUMNS = ("y", "label", "distance", "run", "split", "time", "timestamp")
#: further non-sensor columns a dataset export may hold (text, not carried to the output)
TEXT_COLUMNS = ("features", "class", "row_index")


def _read_npz(path: Path) -> tuple[np.ndarray, dict]:
    try:
        npz = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise UserError(f"Cannot read {path} as an .npz file: {exc}") from None
    with npz:
        names = list(npz.files)
        if "X" in names:
            X = npz["X"]
        elif len(names) == 1:
            X = npz[names[0]]
        else:
            raise UserError(f"{path} has no array named 'X' (it has {', '.join(names) or 'none'}).")
        extras = {k: npz[k] for k in names if k in META_COLUMNS}
    return X, extras


def _read_csv(path: Path) -> tuple[np.ndarray, dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    if not rows:
        raise UserError(f"{path} is empty.")

    def numeric(cell: str) -> bool:
        try:
            float(cell)
            return True
        except ValueError:
            return False

    header = None if all(numeric(c) for c in rows[0]) else [c.strip() for c in rows[0]]
    first_line = 2 if header else 1
    body = rows[1:] if header else rows
    if not body:
        raise UserError(f"{path} has a header but no scans.")
    width = len(header or body[0])
    header = header or [f"s{i}" for i in range(width)]
    for i, row in enumerate(body):
        if len(row) != width:
            raise UserError(f"{path}, line {i + first_line}: {len(row)} values, expected {width}.")
    names = [name.lower() for name in header]
    sensors = [j for j, name in enumerate(names) if name not in META_COLUMNS + TEXT_COLUMNS]
    values = np.empty((len(body), len(sensors)))
    for i, row in enumerate(body):
        for k, j in enumerate(sensors):
            try:
                values[i, k] = float(row[j])
            except ValueError:
                raise UserError(f"{path}, line {i + first_line}: column {header[j]!r} holds {row[j]!r}, "
                                "which is not a number.") from None
    extras = {names[j]: _column([row[j] for row in body]) for j in range(width) if names[j] in META_COLUMNS}
    return values, extras


def _column(cells: list[str]) -> np.ndarray:
    """A metadata column: numbers where every cell is one, else text (e.g. split)."""
    try:
        return np.array([float(c) for c in cells])
    except ValueError:
        return np.array(cells)


def read_scans(path) -> tuple[np.ndarray, dict]:
    """Scans from a CSV (one row a scan, optional header) or an NPZ (array ``X``).

    Columns (or arrays) named ``y``, ``label``, ``distance``, ``run``,
    ``split``, ``time``/``timestamp`` are not sensors: they are returned in
    the second value and carried to the output.
    """
    path = Path(path)
    if not path.exists():
        raise UserError(f"Data file not found: {path}")
    if path.is_dir():
        raise UserError(f"{path} is a folder; expected a .csv or .npz file of scans.")
    X, extras = _read_npz(path) if path.suffix.lower() == ".npz" else _read_csv(path)
    X = np.asarray(X)
    if X.ndim != 2 or X.shape[0] == 0 or X.shape[1] == 0:
        raise UserError(f"{path}: expected a table of scans (rows) by sensors (columns); got shape {X.shape}.")
    if not np.issubdtype(X.dtype, np.number) or not np.all(np.isfinite(X)):
        raise UserError(f"{path}: the scans must be finite numbers.")
    if "timestamp" in extras and "time" not in extras:
        extras["time"] = extras.pop("timestamp")
    return X.astype(np.float64), extras


def write_novelty(path, novelty: np.ndarray, extras: dict) -> None:
    """One row a scan: ``scan, novelty`` and the carried columns; ``-`` or ``None`` is stdout."""
    columns = {"scan": np.arange(novelty.size), "novelty": novelty}
    for name in ("y", "label", "distance", "run", "time"):
        if name in extras and np.asarray(extras[name]).shape == novelty.shape:
            columns[name] = np.asarray(extras[name])
    if path not in (None, "-") and Path(path).suffix.lower() == ".npz":
        with open(path, "wb") as fh:
            np.savez(fh, **columns)
        return
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(list(columns))
    for i in range(novelty.size):
        writer.writerow([_cell(columns[c][i]) for c in columns])
    if path in (None, "-"):
        sys.stdout.write(buffer.getvalue())
    else:
        Path(path).write_text(buffer.getvalue(), encoding="utf-8")


def _cell(value) -> str:
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.10g}"
    return str(value.item() if hasattr(value, "item") else value)
