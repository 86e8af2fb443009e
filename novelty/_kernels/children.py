"""The kernels' child processes: compilers that fill numba's disk cache, and the tricks' self-check.

A child is isolated from the user's working directory and ``PYTHON*``
variables (:func:`_child`), so that it imports the same numba and novelty as
its parent and nothing else. Processes that need one module at once (test
workers, benchmark workers) compile it once: the first holds a lock file
beside the cache while its child compiles (:func:`one_compiler`), the others
wait for it and load what it cached.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import sys

from . import tricks

try:
    import fcntl
except ImportError:  # Windows: no lock; each process compiles what it does not find cached
    fcntl = None

__all__ = ["spawn", "run_self_check", "one_compiler", "lock_path"]

#: what a compiling child runs: ``python -I -c _CHILD count name file ... path...``, ``count``
#: modules by name and file (file "": a module found on the path), one after another; one
#: that fails leaves the others to compile
_CHILD = """
import importlib, importlib.util, sys
count = int(sys.argv[1])
jobs = sys.argv[2:2 + 2 * count]
sys.path[:0] = sys.argv[2 + 2 * count:]
failed = False
for name, file in zip(jobs[::2], jobs[1::2]):
    try:
        if file:
            spec = importlib.util.spec_from_file_location(name, file)
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module
            spec.loader.exec_module(module)
        else:
            importlib.import_module(name)
    except Exception:
        sys.modules.pop(name, None)
        failed = True
sys.exit(1 if failed else 0)
"""

#: what the self-check's child runs: ``python -I -c _PROBE path...`` (:mod:`._probe`)
_PROBE = "import sys; sys.path[:0] = sys.argv[1:]; from novelty._kernels import _probe; _probe.main()"


def spawn(modules: list):
    """A child process compiling ``modules`` one after another (a ``subprocess.Popen``), or None."""
    jobs = [part for compiled in modules for part in (compiled.name, compiled.file or "")]
    return _child(_CHILD, [str(len(modules)), *jobs])


def run_self_check() -> tuple[bool, str]:
    """Run the self-check of the kernels' tricks (:mod:`._probe`) in a child; whether it passed,
    and why not."""
    import subprocess  # a local import: as in _child

    child = _child(_PROBE, [], {tricks.VARIABLE: "1", "NUMBA_NRT_STATS": "1"}, stderr=subprocess.PIPE)
    if child is None:
        return False, "no Python to run it in"
    _, err = child.communicate()
    lines = err.decode(errors="replace").strip().splitlines()
    if child.returncode == 0:
        return True, ""
    if child.returncode < 0:
        return False, f"the check crashed (signal {-child.returncode})"
    return False, lines[-1] if lines else f"the check exited with status {child.returncode}"


def _child(code: str, args: list[str], env_extra: dict | None = None, stderr=None):
    """A child process running ``code`` with ``args`` (a ``subprocess.Popen``), or None.

    The child is isolated (``-I``: neither the working directory nor
    ``PYTHONPATH`` nor user site-packages on its path) and runs in the
    folder that holds the package; it is given this process's absolute
    ``sys.path`` entries, so it imports the same numba and novelty that
    this process will, and never a module that happens to lie in the
    working directory. It is told whether the kernels' tricks are in use
    (:mod:`.tricks`), so that it compiles what this process decided.
    """
    import subprocess  # a local import: a share of `import novelty` that only a cold cache needs

    if not sys.executable:
        return None
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    path = [root] + [p for p in sys.path if p and os.path.isabs(p) and p != root]
    env = dict(os.environ)
    if env.get("NUMBA_CACHE_DIR"):  # the child runs elsewhere: a relative folder would move
        env["NUMBA_CACHE_DIR"] = os.path.abspath(env["NUMBA_CACHE_DIR"])
    if tricks.known() is not None:
        env[tricks.VARIABLE] = "1" if tricks.enabled() else "0"
    env.update(env_extra or {})
    return subprocess.Popen([sys.executable, "-I", "-c", code, *args, *path], cwd=root, env=env,
                            stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL if stderr is None else stderr)


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
def one_compiler(source: str):
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
