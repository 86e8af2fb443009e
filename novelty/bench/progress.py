"""Progress of a run: a tqdm bar with an ETA on a terminal, plain lines otherwise.

Plain lines are used when the stream is not a terminal, when ``CI`` is set (as
CI services do), or when tqdm is not installed; they say which cell finished,
how it went and how many are left, one line a cell, nothing else.
"""

from __future__ import annotations

import os
import sys
import time
from typing import TextIO

from .._progress import use_bar

__all__ = ["Progress", "use_bar"]


def _columns(stream) -> int:
    try:
        return os.get_terminal_size(stream.fileno()).columns
    except (AttributeError, OSError, ValueError):
        return 0


def _short(row: dict) -> str:
    what = f"{row['detector']} / {row['task']} / seed {row['seed']}"
    if row.get("status") != "ok":
        return f"{what}: FAILED {row.get('error', '')}"
    auc = row.get("roc_auc")
    auc_text = "nan" if auc is None or auc != auc else f"{auc:.3f}"
    return f"{what}: AUC {auc_text}"


class Progress:
    """Report finished cells to ``stream`` (stderr by default)."""

    def __init__(self, total: int, stream: TextIO | None = None, bar: bool | None = None,
                 quiet: bool = False):
        self.total = total
        self.done = 0
        self.failed = 0
        self.stream = stream if stream is not None else sys.stderr
        self.quiet = quiet
        self.start = time.perf_counter()
        self._bar = None
        if not quiet and (use_bar(self.stream) if bar is None else bar):
            # optional dependency, imported only to show a progress bar
            from tqdm import tqdm

            sized = _columns(self.stream) > 0  # a pseudo-terminal may report 0 columns
            self._bar = tqdm(total=total, file=self.stream, unit="cell", dynamic_ncols=sized,
                             ncols=None if sized else 100, nrows=None if sized else 24)

    def update(self, row: dict) -> None:
        self.done += 1
        self.failed += row.get("status") != "ok"
        if self.quiet:
            return
        if self._bar is not None:
            self._bar.set_postfix_str(f"{row['detector']} / {row['task']}", refresh=False)
            self._bar.update(1)
            if row.get("status") != "ok":
                self._bar.write(_short(row), file=self.stream)
            return
        width = len(str(self.total))
        print(f"[{self.done:>{width}}/{self.total}] {_short(row)}", file=self.stream, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
