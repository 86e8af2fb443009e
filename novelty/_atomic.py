"""Writing a file whole or not at all: a unique temporary file beside it, then a rename.

Readers of ``path`` see the old file or the new one, never a part; two
writers never share a temporary file; a writer that fails or is killed
leaves ``path`` as it was. The file gets the mode a plain ``open`` would
give it (``0o666`` less the umask), not the private ``0o600`` of
:func:`tempfile.mkstemp`.

Only a regular file is replaced. The rename replaces whatever directory
entry ``path`` is, so a device node, a FIFO, a socket or a symbolic link at
``path`` would be swapped for a regular file (as root, ``/dev/null`` for the
whole system): such a target is refused, before anything is written and
again just before the rename, with :class:`NotARegularFileError`. Nothing is
written through a link: the temporary file is created with ``O_EXCL``, which
never follows one.
"""

from __future__ import annotations

import os
import secrets
import stat
from pathlib import Path
from typing import IO, Callable

__all__ = ["write_atomically", "NotARegularFileError", "check_target", "not_regular", "same_file", "inside"]

_KINDS = ((stat.S_ISLNK, "a symbolic link"), (stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISSOCK, "a socket"))


class NotARegularFileError(FileExistsError):
    """The target exists and is not a regular file, so it is not replaced."""


def not_regular(path: str | os.PathLike, follow: bool = True) -> str | None:
    """What ``path`` is ("a FIFO (named pipe)", ...) if it exists and is not a regular file, else None.

    Reading such a file may never end (``/dev/zero``) or never start (a FIFO
    without a writer); ``follow=False`` looks at a link itself.
    """
    try:
        mode = (os.stat if follow else os.lstat)(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return None
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def check_target(path: str | os.PathLike) -> None:
    """Raise :class:`NotARegularFileError` if ``path`` exists and is not a regular file (links not followed)."""
    kind = not_regular(path, follow=False)
    if kind is None:
        return
    raise NotARegularFileError(
        f"Not written: {os.fspath(path)} exists and is {kind}; only a regular file is replaced "
        "(choose another path, or remove it first).")


def same_file(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether ``a`` and ``b`` name one file: one path once resolved (links followed), or one inode (a hard link)."""
    if Path(a).resolve() == Path(b).resolve():
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:   # one of them does not exist (yet): not one file
        return False


def inside(path: str | os.PathLike, folder: str | os.PathLike) -> bool:
    """Whether ``path`` lies in ``folder`` or below it (both resolved, links followed)."""
    return Path(folder).resolve() in Path(path).resolve().parents


def write_atomically(path: str | os.PathLike, write: Callable[[IO], None], *, text: bool = False,
                     check: Callable[[Path], None] | None = None) -> Path:
    """Write ``path`` through ``write(file)``; ``check(temporary_path)`` may refuse it first.

    Returns ``path``. An exception from ``write`` or ``check`` removes the
    temporary file and propagates; ``path`` is untouched. A ``path`` that
    exists and is not a regular file raises :class:`NotARegularFileError`.
    """
    path = Path(path)
    check_target(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the umask applies
    try:
        with (os.fdopen(fd, "w", encoding="utf-8", newline="") if text else os.fdopen(fd, "wb")) as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        if check is not None:
            check(tmp)
        check_target(path)  # it may have appeared while the file was written
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path
