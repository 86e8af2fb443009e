"""Compiling a module of kernels without making anyone wait: in a child process, cached on disk.

numba is imported only when the first kernel is asked for, so ``import
novelty`` does not pay for it. Compiling a module of kernels takes seconds;
numba caches the machine code on disk (``cache=True``, in ``NUMBA_CACHE_DIR``
when set) and later processes load it in a fraction of a second (at once,
when the cache holds it). So that no call waits for the compiler, a
background thread has a child process compile the module into the cache
(numba's compiler would hold this process's GIL) and then loads it from
there; meanwhile the caller runs the reference (:mod:`.handover`). A process
that ends early waits for the thread at exit, so that the cache gets written;
Ctrl-C during that wait stops the compiler and exits quietly with status 130.
Processes that need one module at once (test workers, benchmark workers) compile
it once: the first holds a lock file beside the cache while its child compiles,
the others wait for it and load what it cached.
The child runs isolated (``python -I``, in the package's folder): nothing in
the user's working directory or ``PYTHON*`` variables is imported or read.

A module that fails (numba missing or failing) is reported by one
``RuntimeWarning`` and never retried; ``NOVELTY_NO_KERNELS`` set to a non-empty
value other than ``0`` when a module is first asked for disables it.
"""

from __future__ import annotations

import atexit
import contextlib
import glob
import hashlib
import importlib
import importlib.util
import os
import sys
import threading
import warnings

try:
    import fcntl
except ImportError:  # Windows: no lock; each process compiles what it does not find cached
    fcntl = None

__all__ = ["Compiled", "cache_files", "disabled", "load"]

#: what the compiling child runs: ``python -I -c _CHILD module file path...`` (file: "" for a
#: module found on the path)
_CHILD = ("import importlib, importlib.util, sys; sys.path[:0] = sys.argv[3:]; "
          "name, file = sys.argv[1:3]; spec = file and importlib.util.spec_from_file_location("
          "name, file); module = spec and importlib.util.module_from_spec(spec); "
          "sys.modules.update({name: module} if spec else {}); "
          "spec.loader.exec_module(module) if spec else importlib.import_module(name)")

#: every module of kernels made in this process, for fork handling and :func:`wait_all`
_all: list["Compiled"] = []


#: the environment's own mapping and the variable's key in it: read on every learning call,
#: where ``os.environ.get`` of a missing variable raises and catches a KeyError (about 1 us)
_ENVIRON = getattr(os.environ, "_data", None)
_KEY = os.environ.encodekey("NOVELTY_NO_KERNELS") if _ENVIRON is not None else None


def disabled() -> bool:
    """Whether ``NOVELTY_NO_KERNELS`` asks for the reference loops."""
    if _ENVIRON is not None:
        value = _ENVIRON.get(_KEY)
        return value is not None and os.environ.decodevalue(value) not in ("", "0")
    return os.environ.get("NOVELTY_NO_KERNELS", "") not in ("", "0")


def load(name: str, file: str | None):
    """Import module ``name`` (from ``file`` when given: a generated driver)."""
    module = sys.modules.get(name)
    if module is not None:
        return module
    if file is None:
        return importlib.import_module(name)
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
    compiled by a child process that a background thread waits for, while the
    caller goes on with the reference."""

    def __init__(self, name: str, file: str | None = None, label: str | None = None):
        self.name = name
        self.file = file  # a generated driver's path; None: a module of the package
        self.label = label or name.rsplit(".", 1)[-1]
        self.module = None  # once ready
        self.failed = False  # numba missing, broken or disabled: never retried
        self.started = False
        self.thread: threading.Thread | None = None  # the background compiler, if one runs
        self.error: BaseException | None = None  # raised in the thread, warned about here
        self.child = None  # the compiling child process (a subprocess.Popen), while it runs
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
            # A daemon joined at exit by _wait_at_exit, not by the interpreter, which would
            # report Ctrl-C during that wait as a traceback and exit with status 0.
            self.thread = threading.Thread(target=self._compile, name=f"novelty-{self.label}",
                                           daemon=True)
            self.thread.start()
            atexit.register(self._wait_at_exit)
        return None

    def _wait_at_exit(self) -> None:
        try:
            if self.thread is not None:
                self.thread.join()
        except KeyboardInterrupt:
            child = self.child
            if child is not None and child.poll() is None:
                child.kill()
            for stream in (sys.stdout, sys.stderr):
                try:
                    stream.flush()
                except (AttributeError, OSError, ValueError):
                    pass
            os._exit(130)  # 128 + SIGINT, as the command line returns for Ctrl-C

    def _compile(self) -> None:
        try:
            if self.name not in sys.modules and not self._cached():
                with _one_compiler(self._source()):
                    if not self._cached():  # another process may have compiled it while this one waited
                        self._compile_in_child()
            self.module = load(self.name, self.file)  # loads what the child cached
        except BaseException as exc:  # ImportError, or numba/LLVM failing to compile or load
            self.error = exc

    def _source(self) -> str:
        """The module's source file ("" if it cannot be found)."""
        if self.file is not None:
            return self.file
        spec = importlib.util.find_spec(self.name)
        return (spec.origin if spec is not None else "") or ""

    def _cached(self) -> bool:
        """Whether numba's disk cache seems to hold this module's kernels (an index file).

        A stale index only costs speed: the import then compiles in this thread.
        """
        source = self._source()
        stem = os.path.splitext(os.path.basename(source))[0]
        return bool(stem) and bool(cache_files(stem, source, ("nbi",)))

    def _compile_in_child(self) -> None:
        """Compile in a child process, which leaves the machine code in numba's disk cache.

        In a thread of this process numba's compiler holds the GIL for long
        stretches: the main thread, learning with the reference meanwhile, was
        measured 40x slower. A child that fails leaves no cache; the import in
        the thread then compiles after all.

        The child is isolated (``-I``: neither the working directory nor
        ``PYTHONPATH`` nor user site-packages on its path) and runs in the
        folder that holds the package; it is given this process's absolute
        ``sys.path`` entries, so it imports the same numba and novelty that
        this process will, and never a module that happens to lie in the
        working directory.
        """
        import subprocess  # a local import: 3 ms of `import novelty` for a cold cache only

        if not sys.executable:
            return
        root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        path = [root] + [p for p in sys.path if p and os.path.isabs(p) and p != root]
        env = dict(os.environ)
        if env.get("NUMBA_CACHE_DIR"):  # the child runs elsewhere: a relative folder would move
            env["NUMBA_CACHE_DIR"] = os.path.abspath(env["NUMBA_CACHE_DIR"])
        self.child = subprocess.Popen(
            [sys.executable, "-I", "-c", _CHILD, self.name, self.file or "", *path], cwd=root,
            env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL)
        try:
            self.child.wait()
        finally:
            self.child = None

    def wait(self, timeout: float | None = None):
        self.get()
        if self.thread is not None:
            self.thread.join(timeout)
        return self.get()

    @property
    def compiling(self) -> bool:
        return self.started and self.module is None and not self.failed and self.error is None

    @property
    def ready(self) -> bool:
        return self.module is not None or self.get() is not None


def lock_path(source: str) -> str:
    """The lock file of compiling ``source``: in ``NUMBA_CACHE_DIR`` when that is set (named by a
    hash of the source's path), else in the ``__pycache__`` beside the source, where numba caches it."""
    stem = os.path.splitext(os.path.basename(source))[0]
    cache_dir = os.environ.get("NUMBA_CACHE_DIR")
    if cache_dir:
        digest = hashlib.sha256(os.path.abspath(source).encode()).hexdigest()[:16]
        return os.path.join(os.path.abspath(cache_dir), f"{stem}-{digest}.compiling")
    return os.path.join(os.path.dirname(os.path.abspath(source)), "__pycache__", f"{stem}.compiling")


@contextlib.contextmanager
def _one_compiler(source: str):
    """Hold the lock of compiling ``source`` (waiting for a process that holds it) while the body
    runs; without a lock when none can be made (Windows, a folder that cannot be written).

    The lock is the operating system's (``flock``): a process that dies lets it go.
    """
    try:
        if fcntl is None or not source:
            raise OSError("no lock")
        path = lock_path(source)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        handle = open(path, "a")
    except OSError:
        yield
        return
    with handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        yield


def _after_fork_in_child() -> None:
    # A compiler thread does not survive fork(); a child forked while one was
    # running would wait for it forever, so it starts its own when it needs one.
    for compiled in _all:
        if compiled.module is None and compiled.error is None:
            compiled.started, compiled.thread = False, None


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def live() -> list[Compiled]:
    """Every module of kernels asked for in this process."""
    return list(_all)
