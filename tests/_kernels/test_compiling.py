"""The kernels' machinery: compiling in a child process, readiness, fallbacks.

No timing is asserted (``benchmarks/perf.py`` measures speed).
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest

import novelty
from novelty import _kernels
from novelty._kernels import children, choice, compiling, drivers

from .kernel_helpers import corridor, reference_only

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


def test_missing_numba_falls_back_with_one_warning(monkeypatch):
    monkeypatch.setattr(compiling, "_all", [])
    monkeypatch.setattr(drivers, "_drivers", {})
    monkeypatch.setattr(choice, "NEAREST", compiling.Compiled("novelty._kernels._nearest"))
    for name in [n for n in sys.modules if n.startswith("novelty_driver_")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.delitem(sys.modules, "novelty._kernels._nearest")
    monkeypatch.delattr(_kernels, "_nearest", raising=False)
    monkeypatch.setitem(sys.modules, "numba", None)  # makes "import numba" fail
    X = corridor(50)
    det = novelty.make("hsom")
    with pytest.warns(RuntimeWarning, match="reference numpy loops"):
        det.fit(X[:1])
        assert _kernels.wait(det.clusterer_, det.synapse_) is None
        assert _kernels.wait() is None
    assert det.compiled_.startswith("reference (kernels unavailable")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = np.concatenate([det.stream(X), [det.score_learn_one(X[0])], det.novelty(X)])
    with reference_only():
        ref = novelty.make("hsom").fit(X[:1])
        expected = np.concatenate([ref.stream(X), [ref.score_learn_one(X[0])], ref.novelty(X)])
    np.testing.assert_array_equal(got, expected)


@pytest.mark.slow
def test_a_driver_is_generated_once_and_loaded_from_numbas_cache(tmp_path):
    """A second process finds the pair's driver file and its machine code: no compiling."""
    code = ("import sys, time, numpy as np, novelty\n"
            "from novelty import _kernels\n"
            "det = novelty.make('hsom', n_rows=3, n_columns=3).fit(np.zeros((2, 5)))\n"
            "compiled = _kernels.engine.driver_of(det.clusterer_, det.synapse_)\n"
            "cached = compiled._cached()\n"
            "assert compiled.wait(timeout=600) is not None, compiled.error\n"
            "stats = compiled.module.drive.stats\n"
            "print(compiled.file, cached, compiled.background, len(stats.cache_misses),\n"
            "      sum(stats.cache_hits.values()))\n")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    runs = [subprocess.run([sys.executable, "-c", code], env=env, check=True, timeout=900,
                           capture_output=True, text=True).stdout.split() for _ in range(2)]
    assert runs[0][0] == runs[1][0] and runs[0][0].startswith(str(tmp_path / "cache"))
    assert runs[0][1:3] == ["False", "True"]  # cold: compiled by a child, queued for the background
    assert runs[1][1:3] == ["True", "False"]  # warm: loaded at once
    # and this process compiled nothing: the machine code, parameter records and all, came from
    # numba's cache (the child's in the first run)
    assert runs[0][3:] == runs[1][3:] == ["0", "1"]


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork()")
def test_a_child_forked_while_compiling_compiles_for_itself(monkeypatch):
    monkeypatch.setattr(compiling, "_all", [])  # the stand-in below leaves no trace
    monkeypatch.setattr(choice, "NEAREST", compiling.Compiled("novelty._kernels._nearest"))
    blocker = threading.Event()
    busy = threading.Thread(target=blocker.wait)  # a background compiler busy with another module
    busy.start()
    monkeypatch.setattr(compiling, "_worker", busy)
    monkeypatch.setattr(compiling, "_queue", [choice.NEAREST])  # queued behind it
    choice.NEAREST.started = choice.NEAREST.background = True
    try:
        pid = os.fork()
        if pid == 0:  # the child: no compiler thread, no queue; it must compile for itself
            ok = choice.NEAREST.wait(timeout=60) is not None
            os._exit(0 if ok else 1)
        _, status = os.waitpid(pid, 0)
        assert os.waitstatus_to_exitcode(status) == 0
    finally:
        blocker.set()


def test_a_module_another_process_is_compiling_is_waited_for_not_compiled_again(tmp_path, monkeypatch):
    """Two test or benchmark workers that need one uncached module: the second waits for the
    first's lock, then loads what the first cached, compiling nothing itself."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    source = tmp_path / "novelty_driver_waited.py"
    source.write_text("VALUE = 42\n")
    compiled = compiling.Compiled("novelty_driver_waited", str(source))
    compiles = []
    monkeypatch.setattr(compiled, "_compile_in_child", lambda: compiles.append("compiled"))
    monkeypatch.delitem(sys.modules, "novelty_driver_waited", raising=False)
    with children.one_compiler(str(source)):  # "the other process", compiling
        compiled.thread = threading.Thread(target=compiled._compile)
        compiled.thread.start()
        compiled.thread.join(0.5)
        assert compiled.thread.is_alive() and compiled.module is None  # waiting for the lock
        index = tmp_path / "cache" / "its-folder" / "novelty_driver_waited.drive-1.py311.nbi"
        index.parent.mkdir(parents=True)
        index.touch()  # what the other process's compiler leaves in numba's cache
    compiled.thread.join(60)
    assert compiles == [] and compiled.module.VALUE == 42
    assert children.lock_path(str(source)).startswith(str(tmp_path / "cache"))
    sys.modules.pop("novelty_driver_waited", None)


def test_a_module_the_caller_waits_for_is_compiled_at_the_callers_priority(tmp_path, monkeypatch):
    """Background compilers give way to every command (niceness 19); a child the caller blocks on
    is the caller's own work, and a busy machine would leave it almost no CPU time at 19."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(compiling, "_all", [])
    source = tmp_path / "novelty_driver_awaited.py"
    source.write_text("VALUE = 7\n")
    awaited = compiling.Compiled("novelty_driver_awaited", str(source))
    blocker = threading.Event()
    busy = threading.Thread(target=blocker.wait)  # the background compiler, busy with another module
    busy.start()
    monkeypatch.setattr(compiling, "_worker", busy)
    monkeypatch.setattr(compiling, "_queue", [awaited])  # queued behind it
    awaited.started = awaited.background = True
    spawned = []
    monkeypatch.setattr(children, "spawn", lambda modules, niceness=children.NICENESS: spawned.append(
        ([m.name for m in modules], niceness)))   # no child: the module's file is then loaded as it is
    monkeypatch.delitem(sys.modules, "novelty_driver_awaited", raising=False)
    try:
        assert awaited.wait(timeout=60).VALUE == 7
    finally:
        blocker.set()
        sys.modules.pop("novelty_driver_awaited", None)
    assert spawned == [(["novelty_driver_awaited"], 0)] and compiling._queue == []


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(os, "nice"), reason="needs flock and nice (POSIX)")
def test_the_compiling_child_holds_the_modules_lock_to_the_end_at_the_lowest_priority(tmp_path, monkeypatch):
    """The lock is the compiler's own, not its parent's: a command that ends leaves its compiler holding
    it, and the next command waits for it instead of compiling the module again beside it."""
    import fcntl

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(compiling, "_all", [])
    source, started = tmp_path / "novelty_driver_slow.py", tmp_path / "started"
    source.write_text(f"import pathlib, time\npathlib.Path({str(started)!r}).touch()\ntime.sleep(3)\n")
    child = children.spawn([compiling.Compiled("novelty_driver_slow", str(source))])
    try:
        deadline = time.monotonic() + 120
        while not started.exists() and child.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert started.exists(), "the child compiles the module"
        assert os.getpriority(os.PRIO_PROCESS, child.pid) == children.NICENESS
        with open(children.lock_path(str(source)), "a") as fh:
            with pytest.raises(BlockingIOError):
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)   # held by the child while it compiles
            assert child.wait(120) == 0
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)      # and let go when it is done
    finally:
        if child.poll() is None:
            child.kill()


def test_read_only_and_strided_inputs():
    X = corridor(300)
    det, ref = novelty.make("hsom"), novelty.make("hsom")
    frozen = X.copy()
    frozen.setflags(write=False)
    with reference_only():
        expected = np.concatenate([ref.stream(X), ref.novelty(X), [ref.score_one(X[:, 0][:16])]])
    got = np.concatenate([det.stream(frozen), det.novelty(frozen),
                          [det.score_one(np.asfortranarray(X)[:, 0][:16])]])
    np.testing.assert_array_equal(got, expected)


def test_import_novelty_does_not_import_numba():
    code = ("import sys, numpy as np, novelty\n"
            "det = novelty.make('hsom')\n"
            "assert 'numba' not in sys.modules\n"
            "det.fit(np.zeros((2, 3)))\n"
            "novelty._kernels.wait()\n"
            "assert 'numba' in sys.modules\n")
    subprocess.run([sys.executable, "-c", code], check=True)


def _plant_numba(folder):
    """A ``numba.py`` in ``folder`` that leaves a mark when imported, then fails the import."""
    mark = folder / "planted-numba-ran"
    (folder / "numba.py").write_text(f"open({str(mark)!r}, 'w').close()\nraise ImportError('planted')\n")
    return mark


def _script(tmp_path, code: str):
    """``code`` as a script file outside the working directory: its folder, not the cwd, leads sys.path."""
    folder = tmp_path / "script"
    folder.mkdir()
    path = folder / "main.py"
    path.write_text(code)
    return path


@pytest.mark.slow
def test_the_background_compiler_ignores_the_working_directory(tmp_path):
    cwd, cache = tmp_path / "cwd", tmp_path / "cold-cache"
    cwd.mkdir()
    mark = _plant_numba(cwd)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    # The plant works: a plain child started in that folder runs it.
    subprocess.run([sys.executable, "-c", "import numba"], cwd=cwd, env=env, capture_output=True)
    assert mark.exists()
    mark.unlink()
    # The library's compiler child does not (a module that imports numba, compiles nothing).
    script = _script(tmp_path, "from novelty import _kernels\n"
                               "compiled = _kernels.compiling.Compiled('novelty._kernels._distances')\n"
                               "assert compiled.wait(timeout=120) is not None, compiled.error\n")
    subprocess.run([sys.executable, str(script)], cwd=cwd, env=env, check=True, timeout=180)
    assert not mark.exists()


#: a module of one small kernel, compiled when imported, that takes a while to import
SLOW_KERNEL = """
import time
from numba import njit
time.sleep({sleep})
@njit("float64(float64)", cache=True)
def plus_one(x):
    return x + 1.0
"""


@pytest.mark.slow
def test_a_process_ends_without_waiting_for_its_compilers_which_finish_and_cache(tmp_path):
    """One compiler at a time: the first module compiles while the second waits in the queue;
    the process ends at once, the first child finishes by itself and the second is handed to a
    last child; the next process loads both from numba's cache."""
    for name, sleep in (("first_kernels", 3.0), ("second_kernels", 0.0)):
        (tmp_path / f"{name}.py").write_text(SLOW_KERNEL.format(sleep=sleep))
    script = _script(tmp_path, "import sys, time\n"
                               "from novelty._kernels import compiling\n"
                               f"first = compiling.Compiled('first_kernels', {str(tmp_path / 'first_kernels.py')!r})\n"
                               f"second = compiling.Compiled('second_kernels', {str(tmp_path / 'second_kernels.py')!r})\n"
                               "assert first.get() is None and second.get() is None\n"
                               "while first.child is None:\n"
                               "    time.sleep(0.01)\n"
                               "assert compiling._queue == [second]  # one compiler at a time\n"
                               "print(first.child.pid, flush=True)\n")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cold-cache"))
    done = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    pid = int(done.stdout)
    os.kill(pid, 0)  # still compiling (it sleeps 3 s first): the process did not wait for it
    check = ("from novelty._kernels import compiling\n"
             f"modules = [compiling.Compiled(n, {str(tmp_path)!r} + '/' + n + '.py') for n in "
             "('first_kernels', 'second_kernels')]\n"
             "print(all(m._cached() for m in modules))\n")
    deadline = time.monotonic() + 300
    while True:
        cached = subprocess.run([sys.executable, "-c", check], env=env, capture_output=True,
                                text=True, check=True).stdout.strip()
        if cached == "True" or time.monotonic() > deadline:
            break
        time.sleep(1.0)
    assert cached == "True"
    loaded = subprocess.run([sys.executable, "-c", check.replace(
        "print(all(m._cached() for m in modules))",
        "print(all(m.get() is not None and not m.background and m.module.plus_one(1.0) == 2.0 "
        "for m in modules))")], env=env, capture_output=True, text=True, check=True)
    assert loaded.stdout.strip() == "True"  # loaded at once, from the cache


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
def test_hot_path_bounds_scans_and_rejects_nan():
    det = novelty.make("hsom").fit(np.zeros((2, 4)))
    large = np.full(4, 4.9e99)  # norm 9.8e99, just within the bound
    assert det.score_one(large) == det.novelty(large[None, :])[0]
    with pytest.raises(ValueError, match=r"norm above 1e\+100"):
        det.score_one(np.full(4, 1e308))  # finite, but squared distances overflow
    with pytest.raises(ValueError, match="NaN or infinity"):
        det.score_one(np.array([0.0, np.nan, 0.0, 0.0]))
    with pytest.raises(ValueError, match="NaN or infinity"):
        det.learn_one(np.array([0.0, np.inf, 0.0, 0.0]))


