"""Child Python processes that never import code from the working directory.

``python -m module`` and ``python -c code`` put the working directory first on
``sys.path``, so a ``numpy.py``, ``joblib.py`` or ``multiprocessing.py`` lying
in the directory a command is run from would run in every child that starts
that way: loky's workers (``-m``) and resource tracker (``-c``),
multiprocessing's spawned children and resource tracker (``-c``), and so Dask's
local workers. None of them takes extra interpreter arguments from us, but
all inherit the environment, and ``PYTHONSAFEPATH=1`` (Python 3.11 on) tells
each interpreter to leave the working directory off ``sys.path``;
:func:`isolated_children` sets it while children are started. The parent's
own ``sys.path`` is what the children's loky and multiprocessing preparation
copies in afterwards, so they still find everything the parent imports.

On Python 3.10 the variable means nothing: there, run commands that start
workers from a directory holding no Python files of someone else's.
The compiler child (:mod:`novelty._kernels.compiling`) runs with ``-I``.
"""

from __future__ import annotations

import contextlib
import os
from typing import Iterator

__all__ = ["SAFE_PATH", "isolated_children"]

#: the environment that keeps the working directory off a child interpreter's sys.path
SAFE_PATH = {"PYTHONSAFEPATH": "1"}


@contextlib.contextmanager
def isolated_children() -> Iterator[None]:
    """Within the block, child interpreters started from this process do not search the working directory."""
    before = {name: os.environ.get(name) for name in SAFE_PATH}
    os.environ.update(SAFE_PATH)
    try:
        yield
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
