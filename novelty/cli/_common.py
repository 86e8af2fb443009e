"""What the commands share: the parser, user errors, parameters, scan files."""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .._atomic import inside, same_file
from ..datasets.files import PREPROCESSING
from ..registry import RegistryError

__all__ = ["NoveltyParser", "UserError", "one_line", "user_errors", "parse_params", "read_scans",
           "write_novelty", "add_command", "add_data_options", "data_options", "alarms", "format_cell",
           "check_outputs"]


class UserError(Exception):
    """Something the user can fix (a file, a name, a value): one line, exit code 2."""


def one_line(exc: BaseException) -> str:
    text = str(exc.args[0]) if isinstance(exc, KeyError) and exc.args else str(exc)
    text = " ".join(text.split())
    return text or type(exc).__name__


def user_errors() -> tuple[type[BaseException], ...]:
    """Exceptions that mean the input was wrong, not the program."""
    # deferred: the benchmark and the model files import scikit-learn, slow to import; `novelty --help` does not
    from ..bench.backends import BackendError
    from ..bench.specs import SuiteError
    from ..persistence import ModelFileError

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
    # deferred: the benchmark imports scikit-learn; `novelty --help` does not
    from ..bench.specs import SuiteError, parse_assignments

    try:
        return parse_assignments(items or [])
    except SuiteError as exc:
        raise UserError(str(exc)) from None


def check_outputs(reads, writes) -> None:
    """Refuse an output that names a file the command reads, or another output, before anything is done.

    ``reads`` and ``writes`` are ``(option, path)`` pairs (``("--data",
    "scans.csv")``); a path that is None or ``-`` (standard input or output)
    takes no part. One file is one path once resolved or one inode (a hard
    link); a read path that is a folder (a ROS 2 bag) holds every file below it.
    """
    reads = [(option, path) for option, path in reads if path not in (None, "-")]
    writes = [(option, path) for option, path in writes if path not in (None, "-")]
    for i, (option, path) in enumerate(writes):
        for source, read in reads:
            if same_file(path, read):
                raise UserError(f"{option} {path} is the file {source} names: writing it would replace what is "
                                f"read. Choose another {option}.")
            if Path(read).is_dir() and inside(path, read):
                raise UserError(f"{option} {path} lies in {read}, which {source} names and is read. Choose "
                                f"another {option}.")
        for other, earlier in writes[:i]:
            if same_file(path, earlier):
                raise UserError(f"{other} and {option} name one file ({path}): one output would replace the "
                                "other. Give each its own.")


# ----------------------------------------------------------------- scan files
def add_data_options(parser, data_help: str = "scans: .csv or .npz") -> None:
    """``--data`` and the options that say which of its columns are what."""
    parser.add_argument("--data", required=True, metavar="FILE", help=data_help)
    group = parser.add_argument_group("columns of the data file")
    group.add_argument("--columns", metavar="C,C,..",
                       help="sensor columns: names, patterns ('field.ranges*') or 0-based indices "
                       "(default: every column without another role)")
    group.add_argument("--label", metavar="COLUMN",
                       help="label column, non-zero = novel (default: a column named y or label)")
    group.add_argument("--time", metavar="COLUMN",
                       help="time column, used as timestamps, never as a sensor (default: a column "
                       "named time, timestamp, field.header.stamp or %%time; ROS stamps: ns)")
    group.add_argument("--preprocess", choices=PREPROCESSING, default="none",
                       help="'paper': ranges (m) become 1 - min(r, T) / T, the paper's sonar "
                       "preprocessing (default: none, the values as they are)")
    group.add_argument("--range-threshold", type=float, metavar="T",
                       help="T of --preprocess paper, in metres (default: the paper's 4)")
    group.add_argument("--bin-length", type=float, metavar="M",
                       help="average the scans over each M metres of travel (needs a distance column)")


def data_options(args) -> dict:
    """The options of :func:`novelty.datasets.files.read_scans` given on the command line."""
    return dict(columns=args.columns, label=args.label, time=args.time, preprocess=args.preprocess,
                threshold=args.range_threshold, bin_length=args.bin_length)


def read_scans(args):
    """The scans of ``--data`` as a :class:`~novelty.datasets.Dataset` (see :mod:`novelty.datasets.files`)."""
    # deferred: reading scans is not needed to start the command line
    from ..datasets.files import read_scans as read

    try:
        return read(args.data, **data_options(args))
    except FileNotFoundError as exc:
        raise UserError(str(exc)) from None


def carried_columns(data) -> dict:
    """The per-scan values a novelty output carries beside the novelty."""
    columns = {name: getattr(data, name) for name in ("y", "distance", "run") if getattr(data, name) is not None}
    if "time" in data.columns:
        columns["time"] = data.columns["time"]
    return columns


def alarms(det, novelty: np.ndarray) -> np.ndarray | None:
    """1 where the novelty is above the detector's threshold in force (as ``predict`` says -1), else 0.

    That is ``threshold_`` (``threshold``, or what ``contamination`` sets), or
    ``threshold`` for a detector without ``threshold_``; none, no alarms.
    """
    threshold = getattr(det, "threshold_", None) if hasattr(type(det), "threshold_") \
        else getattr(det, "threshold", None)
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.floating)):
        return None
    return (np.asarray(novelty) > threshold).astype(np.int8)


def write_novelty(path, novelty: np.ndarray, data, alarm: np.ndarray | None = None) -> None:
    """One row a scan: ``scan, novelty, alarm`` and the carried columns; ``-`` or ``None`` is stdout."""
    columns = {"scan": np.arange(novelty.size), "novelty": novelty}
    if alarm is not None:
        columns["alarm"] = alarm
    columns.update(carried_columns(data))
    if path not in (None, "-") and Path(path).suffix.lower() == ".npz":
        with open(path, "wb") as fh:
            np.savez(fh, **columns)
        return
    if path in (None, "-"):
        _write_rows(sys.stdout, columns, novelty.size)
    else:
        with open(path, "w", newline="", encoding="utf-8") as fh:
            _write_rows(fh, columns, novelty.size)


def _write_rows(fh, columns: dict, n: int) -> None:
    # a row at a time: a reader that stops early (| head) is noticed at the next row
    writer = csv.writer(fh, lineterminator="\n")
    writer.writerow(list(columns))
    for i in range(n):
        writer.writerow([format_cell(columns[c][i], exact=c == "time") for c in columns])


def format_cell(value, exact: bool = False) -> str:
    """A value as CSV text: floats to 10 digits, or exactly (timestamps: every digit counts)."""
    if isinstance(value, (float, np.floating)):
        return repr(float(value)) if exact else f"{float(value):.10g}"
    return str(value.item() if hasattr(value, "item") else value)
