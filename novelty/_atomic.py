"""Writing a file whole or not at all: a unique temporary file beside it, then a rename.

Readers of ``path`` see the old file or the new one, never a part; two
writers never share a temporary file; a writer that fails or is killed
leaves ``path`` as it was. The file gets the mode a plain ``open`` would
give it (``0o666`` less the umask), not the private ``0o600`` of
:func:`tempfile.mkstemp`.
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path
from typing import IO, Callable

__all__ = ["write_atomically"]


def write_atomically(path: str | os.PathLike, write: Callable[[IO], None], *, text: bool = False,
                     check: Callable[[Path], None] | None = None) -> Path:
    """Write ``path`` through ``write(file)``; ``check(temporary_path)`` may refuse it first.

    Returns ``path``. An exception from ``write`` or ``check`` removes the
    temporary file and propagates; ``path`` is untouched.
    """
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the umask applies
    try:
        with (os.fdopen(fd, "w", encoding="utf-8", newline="") if text else os.fdopen(fd, "wb")) as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        if check is not None:
            check(tmp)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path
