"""Progress of a long job on a stream: a tqdm bar on a terminal, a plain line a step otherwise.

Plain lines are used when the stream is not a terminal, when ``CI`` is set (as
CI services do), or when tqdm (an optional dependency) is not installed.
"""

from __future__ import annotations

import os
import time
from typing import TextIO

__all__ = ["use_bar", "Steps"]


def use_bar(stream: TextIO) -> bool:
    """Whether a live bar suits ``stream``: a terminal, outside CI, with tqdm installed."""
    if os.environ.get("CI", "").lower() not in ("", "0", "false"):
        return False
    if not (hasattr(stream, "isatty") and stream.isatty()):
        return False
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


class Steps:
    """Report each finished step of a job of ``total`` steps called ``what`` to ``stream``.

    >>> import io
    >>> out = io.StringIO()
    >>> with Steps("ablations", 2, out) as steps:
    ...     steps.step(); steps.step()
    >>> [line.split(" (")[0] for line in out.getvalue().splitlines()]
    ['ablations: step 1 of 2', 'ablations: step 2 of 2']
    """

    def __init__(self, what: str, total: int, stream: TextIO, bar: bool | None = None):
        self.what, self.total, self.stream = what, total, stream
        self.done = 0
        self.start = time.perf_counter()
        self._bar = None
        if use_bar(stream) if bar is None else bar:
            # optional dependency, imported only to show a bar
            from tqdm import tqdm

            self._bar = tqdm(total=total, file=stream, desc=what, unit="step")

    def step(self) -> None:
        self.done += 1
        if self._bar is not None:
            self._bar.update(1)
            return
        print(f"{self.what}: step {self.done} of {self.total} ({time.perf_counter() - self.start:.0f} s)",
              file=self.stream, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()

    def __enter__(self) -> "Steps":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
