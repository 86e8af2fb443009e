"""Whether the drivers use their two tricks on numba's internals: decided by a self-check, once.

Two pieces of the compiled loop lean on numba and llvmlite beyond ``@njit``,
each for a gain measured on the online HSOM's stream against the plain kernel
(docs/guide/performance.md): arrays that numba does not reference-count
(:mod:`._uncounted`) and four weights moved in one LLVM vector
(:mod:`._lanes`). A numba that changed what they rely on could turn them into
wrong numbers or a crash, so each has a plain twin written on ``@njit`` alone,
and the tricks are used only while a self-check passes: before the first
driver is compiled with them (per numba, llvmlite and package sources,
:func:`key`), a child process compiles :mod:`._probe` and runs each trick
against its twin, bit for bit, with numba's allocation counts balanced. A
child that fails the check, cannot compile it or crashes turns the tricks off:
one ``RuntimeWarning`` says so, and every driver compiles plain (the same
numbers, more slowly). The verdict is kept in a file beside the generated
drivers, so later processes read it instead of checking again.

``NOVELTY_KERNEL_TRICKS=0`` turns the tricks off (for comparisons); a
compiling child is told its parent's choice through the same variable. No
numba here: the generated drivers' sources name the choice (a driver
compiled with the tricks is never loaded for one without).
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import os
import warnings

__all__ = ["enabled", "known", "decide", "key", "read", "write"]

#: the variable that forces the choice ("0" off, "1" on)
VARIABLE = "NOVELTY_KERNEL_TRICKS"

_verdict: bool | None = None  # this process's: None until read or checked


def enabled() -> bool:
    """Whether the tricks are in use: the variable's word, else the verdict, else (not checked
    yet) True: a process asks :func:`known` before it compiles a driver with them."""
    forced = os.environ.get(VARIABLE)
    if forced in ("0", "1"):
        return forced == "1"
    return _verdict is not False


def known() -> bool | None:
    """The choice if it is made (the variable, or a verdict), else None."""
    forced = os.environ.get(VARIABLE)
    if forced in ("0", "1"):
        return forced == "1"
    return _verdict


def decide(ok: bool, why: str = "") -> None:
    """Take the self-check's verdict; a failed one is reported once."""
    global _verdict
    _verdict = ok
    if not ok:
        warnings.warn(
            f"novelty: the compiled kernels' tricks on numba's internals failed their self-check "
            f"({why}); using the plain kernels, which give the same results more slowly.",
            RuntimeWarning, stacklevel=2)


def key(package_digest: str) -> str:
    """What a verdict holds for: numba's and llvmlite's versions and the package's sources."""
    versions = []
    for name in ("numba", "llvmlite"):
        try:
            versions.append(importlib.metadata.version(name))
        except importlib.metadata.PackageNotFoundError:
            versions.append("-")
    return hashlib.sha256("\0".join(versions + [package_digest]).encode()).hexdigest()[:16]


def read(folder: str, digest: str) -> bool | None:
    """The verdict kept in ``folder`` for these versions, or None."""
    for ok, suffix in ((True, ".ok"), (False, ".failed")):
        if os.path.exists(os.path.join(folder, f"tricks-{key(digest)}{suffix}")):
            return ok
    return None


def write(folder: str, digest: str, ok: bool, why: str = "") -> None:
    """Keep the verdict in ``folder`` (a hint only: nothing is lost when it cannot be written)."""
    try:
        with open(os.path.join(folder, f"tricks-{key(digest)}{'.ok' if ok else '.failed'}"), "w",
                  encoding="utf-8") as f:
            f.write(why)
    except OSError:
        pass
