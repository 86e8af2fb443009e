"""Compiling a module of kernels without making anyone wait: in a child process, cached on disk.

numba is imported only when the first kernel is asked for, so ``import
novelty`` does not pay for it. Compiling a module of kernels takes seconds;
numba caches the machine code on disk (``cache=True``, in ``NUMBA_CACHE_DIR``
when set) and later processes load it in a fraction of a second (at once,
when the cache holds it). So that no call waits for the compiler, a
background thread has a child process compile the module into the cache
(numba's compiler would hold this process's GIL) and then loads it from
there; meanwhile the caller runs the reference (:mod:`.handover`), with the
same results.

**One compiler at a time, and nobody waits for it at exit.** The modules
asked for queue for one background thread, which compiles them one after
another: on two cores, five compilers at once took both cores from the work
they were compiling for. A process that ends while a child compiles does not
wait for it: the child is a process of its own and finishes writing numba's
cache; the modules still queued are handed to one last child, which compiles
them one by one after the process is gone, and the next process loads them
(``novelty bench --quick`` with an empty cache took far longer when five
compilers ran at once and the command waited for them at exit:
docs/guide/performance.md; it needs none of its kernels to be fast, its cells
are short).
The children stay in the caller's process group, so Ctrl-C stops them too
(nothing is cached then; a later process compiles again).
:meth:`Compiled.wait` compiles a module that is still queued at once, in a
child of its own, and blocks until it is ready.

Processes that need one module at once compile it once
(:func:`.children.one_compiler`).

Every child runs isolated (``python -I``, in the package's folder): nothing
in the user's working directory or ``PYTHON*`` variables is imported or read.
A module that fails (numba missing or failing) is reported by one
``RuntimeWarning`` and never retried; ``NOVELTY_NO_KERNELS`` set to a
non-empty value other than ``0`` when a module is first asked for disables it.
"""

from __future__ import annotations

import atexit
import glob
import importlib
import importlib.util
import os
import sys
import threading
import warnings
from typing import Callable

from . import children
from .environment import disabled

__all__ = ["Compiled", "cache_files", "disabled", "load"]

#: every module of kernels made in this process, for fork handling and :func:`live`
_all: list["Compiled"] = []
#: the modules waiting for the background compiler, in the order asked for, and its thread
_queue: list["Compiled"] = []
_worker: threading.Thread | None = None
_queue_lock = threading.Lock()
_handed_over_at_exit = False


#: held while a generated driver is loaded: a module is in ``sys.modules`` before its code has run
_loading = threading.Lock()


def load(name: str, file: str | None):
    """Import module ``name`` (from ``file`` when given: a generated driver)."""
    if file is None:
        return importlib.import_module(name)  # the import system's own lock per module
    with _loading:  # another thread's half-run module is never returned as loaded
        module = sys.modules.get(name)
        if module is not None:
            return module
        spec = importlib.util.spec_from_file_location(name, file)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[name]
            raise
        return module


def cache_files(stem: str, source: str, kinds: tuple = ("nbi", "nbc")) -> list[str]:
    """numba's cache files (of these kinds: ``nbi`` the index, ``nbc`` the code) of the module
    ``stem`` whose source is ``source``: in ``NUMBA_CACHE_DIR/<a folder per source folder>/``
    when that is set, else in ``__pycache__`` beside the source."""
    cache_dir = os.environ.get("NUMBA_CACHE_DIR")
    folders = (glob.glob(os.path.join(cache_dir, "*")) if cache_dir
               else [os.path.join(os.path.dirname(os.path.abspath(source or ".")), "__pycache__")])
    return [found for folder in folders for kind in kinds
            for found in glob.glob(os.path.join(glob.escape(folder), f"{glob.escape(stem)}.*.{kind}"))]


class Compiled:
    """One module of kernels: loaded at once when numba's disk cache holds it, else
    compiled by a child process of the background compiler (one module at a time), while
    the caller goes on with the reference."""

    def __init__(self, name: str | None, file: str | None = None, label: str | None = None,
                 resolve: Callable[[bool], tuple[str, str] | None] | None = None):
        self.name = name
        self.file = file  # a generated driver's path; None: a module of the package
        self.label = label or name.rsplit(".", 1)[-1]
        # a generated driver's: ``resolve(settle)`` writes it and gives its name and file, or
        # None while that waits for a decision only ``settle=True`` may take (:mod:`.tricks`)
        self.resolve = resolve
        self.module = None  # once ready
        self.failed = False  # numba missing, broken or disabled: never retried
        self.started = False
        self.background = False  # queued for (or compiled by) the background compiler
        self.done = threading.Event()  # set when compiling (or loading) ended, ready or not
        self.error: BaseException | None = None  # raised while compiling, warned about by get()
        self.child = None  # the compiling child process (a subprocess.Popen), while it runs
        self.owner: threading.Thread | None = None  # the background compiler that took it
        _all.append(self)

    def get(self):
        """The module if ready; else start compiling it (once) and return None."""
        if self.module is not None:
            return self.module
        if self.failed:
            return None
        if self.error is not None:
            self.failed = True
            warnings.warn(
                f"novelty: compiled kernels are unavailable for {self.label} "
                f"({type(self.error).__name__}: {self.error}); using the reference numpy loops, "
                "which give the same results more slowly.",
                RuntimeWarning,
                stacklevel=5,
            )
            return None
        if not self.started:
            if disabled():
                return None
            self.started = True
            if self._cached():
                # Loading takes a fraction of a second: less than sharing the GIL
                # with a loader thread would cost the caller, so load now.
                self._compile()
                return self.get()
            self.background = True
            _enqueue(self)
        return None

    def _resolved(self, settle: bool) -> bool:
        """Whether the module's name and file are known (a generated driver's: written again if
        another process pruned it meanwhile)."""
        if self.resolve is None or (self.file is not None and os.path.exists(self.file)):
            return True
        where = self.resolve(settle)
        if where is None:
            return False
        self.name, self.file = where
        return True

    def _compile(self) -> None:
        try:
            self._resolved(settle=True)
            if self.name not in sys.modules and not self._cached():
                with children.one_compiler(self._source()):
                    if not self._cached():  # another process may have compiled it meanwhile
                        self._compile_in_child()
            self.module = load(self.name, self.file)  # loads what the child cached
        except BaseException as exc:  # ImportError, or numba/LLVM failing to compile or load
            self.error = exc
        finally:
            self.done.set()

    def _cached(self) -> bool:
        """Whether numba's disk cache seems to hold this module's kernels (an index file).

        A stale index only costs speed: the import then compiles in this thread.
        """
        if not self._resolved(settle=False):
            return False  # a driver whose file waits for the tricks' self-check: not compiled yet
        source = self._source()
        stem = os.path.splitext(os.path.basename(source or ""))[0]
        return bool(stem) and bool(cache_files(stem, source, ("nbi",)))

    def _source(self) -> str:
        """The module's source file ("" if it cannot be found)."""
        if self.file is not None:
            return self.file
        spec = importlib.util.find_spec(self.name)
        return spec.origin if spec is not None and spec.origin else ""

    def _compile_in_child(self) -> None:
        """Compile in a child process, which leaves the machine code in numba's disk cache.

        In a thread of this process numba's compiler holds the GIL for long
        stretches: the main thread, learning with the reference meanwhile, was
        measured many times slower. A child that fails leaves no cache; the import in
        the thread then compiles after all.
        """
        self.child = children.spawn([self])
        if self.child is None:
            return
        try:
            self.child.wait()
        finally:
            self.child = None

    def wait(self, timeout: float | None = None):
        """The module, compiled (or loaded) now if need be: one still queued for the background
        compiler is taken from the queue and compiled in this thread's own child; None when
        kernels are unavailable, or not ready within ``timeout`` seconds."""
        self.get()
        if self.module is None and not self.failed and self.started:
            owner = self.owner
            if _take(self) or owner is None or not owner.is_alive():
                self._compile()  # queued, or lost by a compiler that is gone: compiled here
            else:
                self.done.wait(timeout)
        return self.get()

    @property
    def compiling(self) -> bool:
        return self.started and self.module is None and not self.failed and self.error is None

    @property
    def ready(self) -> bool:
        return self.module is not None or self.get() is not None


def _enqueue(compiled: Compiled) -> None:
    """Queue ``compiled`` for the background compiler, starting its thread if none runs."""
    global _worker
    with _queue_lock:
        _queue.append(compiled)
        if _worker is None:
            # a daemon: a process that ends does not wait for it (see the module docstring)
            _worker = threading.Thread(target=_work, name="novelty-compiler", daemon=True)
            _worker.start()


def _work() -> None:
    """The background compiler: the queued modules, one at a time, until none is left."""
    global _worker
    while True:
        with _queue_lock:
            if not _queue:
                _worker = None
                return
            compiled = _queue.pop(0)
            compiled.owner = threading.current_thread()
        compiled._compile()


def _take(compiled: Compiled) -> bool:
    """Take ``compiled`` from the queue (True) unless the background compiler has it already."""
    with _queue_lock:
        if compiled in _queue:
            _queue.remove(compiled)
            return True
        return False


def _hand_over_at_exit() -> None:
    """At exit: the modules still queued go to one last child, which compiles them into numba's
    cache after this process is gone (a child compiling already finishes by itself). A driver
    whose file still waits for the tricks' self-check is left to a later process."""
    global _handed_over_at_exit
    with _queue_lock:
        pending = list(_queue)
        _queue.clear()
    if _handed_over_at_exit:
        return
    _handed_over_at_exit = True
    try:
        ready = [compiled for compiled in pending if compiled._resolved(settle=False)]
        if ready:
            children.spawn(ready)
    except (OSError, ImportError, ValueError):  # no folder, no module, no process: a later
        pass  # process compiles them


atexit.register(_hand_over_at_exit)


def _after_fork_in_child() -> None:
    # The compiler thread does not survive fork(): a child forked while it ran would wait for
    # it forever, so it starts its own queue when it needs one.
    global _worker, _queue_lock, _loading
    _queue.clear()
    _worker = None
    _queue_lock = threading.Lock()
    _loading = threading.Lock()  # a thread that held it while loading did not come along
    for compiled in _all:
        if compiled.module is None and compiled.error is None:
            compiled.started = compiled.background = False
            compiled.done = threading.Event()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def live() -> list[Compiled]:
    """Every module of kernels asked for in this process."""
    return list(_all)
