"""Where cells run: in this process, in joblib worker processes, or on Dask.

Each backend is a generator ``execute(cells) -> iterator of (row, arrays)``
yielding every cell's result as soon as it finishes (in any order), so the
caller can record it at once. Cells are pure functions
(:func:`novelty.bench.cell.run_cell`), hence every backend gives the same
numbers for the same suite.

Whatever goes wrong inside a cell is a failed cell, never the end of the run:

- an exception (``SystemExit`` included) is caught by ``run_cell``;
- joblib: cells run in loky worker processes, watched one by one. A worker
  that dies (a segfault, the OOM killer, ``os._exit``) fails its cell; when
  several cells were running, each is run again alone to find the one that
  kills its worker, so a cell is never blamed for another's crash;
- a cell that runs past its timeout (``cell_timeout`` of the suite,
  ``--cell-timeout``) has its worker stopped and is recorded as failed. With a
  timeout, serial runs use one such worker process too (without one, cells
  run in this process, and a cell that kills the process ends the run);
- Dask: a cell whose worker dies is retried by the scheduler, then recorded
  as failed; a cell past its timeout is recorded as failed, but runs on in
  its worker's thread (Dask cannot stop running code).

Every worker process (loky's, its resource tracker, a local Dask cluster's)
is started without the working directory on its ``sys.path``
(:mod:`novelty._children`).
"""

from __future__ import annotations

import contextlib
import threading
import time
from concurrent.futures import FIRST_COMPLETED, BrokenExecutor, wait
from typing import Iterable, Iterator

from .._children import SAFE_PATH, isolated_children
from .cell import failed_row, run_cell, run_cell_in_worker
from .specs import Cell

__all__ = ["BACKENDS", "execute", "BackendError"]

BACKENDS = ("serial", "joblib", "dask")


class BackendError(RuntimeError):
    """A backend that cannot start (missing package, unreachable scheduler)."""


def run_serial(cells: Iterable[Cell], jobs: int = 1, scheduler: str | None = None) -> Iterator[tuple]:
    """In this process, one after the other; cells with a timeout in one watched worker."""
    cells = list(cells)
    if any(c.timeout is not None for c in cells):
        yield from run_watched(cells, 1)
        return
    for cell in cells:
        yield run_cell(cell)


def run_joblib(cells: Iterable[Cell], jobs: int = 2, scheduler: str | None = None) -> Iterator[tuple]:
    """Processes on this machine (joblib's loky executor), ``jobs`` at a time, each cell watched."""
    yield from run_watched(list(cells), jobs)


#: seconds between looks at the running cells' clocks
_POLL = 0.25


def run_watched(cells: list[Cell], jobs: int) -> Iterator[tuple]:
    """Cells in loky worker processes, at most ``jobs`` at once; failures stay with their cell.

    A dead worker breaks the whole pool, so every cell running at the time is
    a suspect: alone, it fails; with others, each suspect runs again alone.
    A cell past its timeout is failed and the pool stopped; the cells that
    were running beside it start again (a cell is a pure function, so a
    restart changes nothing but time).
    """
    # deferred: joblib, slow to import, only for the process backend
    from joblib.externals.loky import get_reusable_executor

    pending = list(reversed(cells))
    suspects: list[Cell] = []
    running: dict = {}  # future -> (cell, start time)
    executor = None
    try:
        while pending or suspects or running:
            if executor is None:
                executor = get_reusable_executor(max_workers=jobs, env=SAFE_PATH)
                # a new pool's workers start and import first; that is not the cells' time
                for job in [executor.submit(_ready) for _ in range(jobs)]:
                    job.result()
            while len(running) < (1 if suspects else jobs) and (suspects or pending):
                cell = suspects.pop() if suspects else pending.pop()
                running[executor.submit(run_cell_in_worker, cell)] = (cell, time.monotonic())
            done, _ = wait(list(running), timeout=_POLL, return_when=FIRST_COMPLETED)
            crashed = []
            for future in done:
                cell, _ = running.pop(future)
                try:
                    yield future.result()
                except Exception as exc:  # noqa: BLE001 - a dead worker, or a cell that cannot be sent
                    if _pool_broken(exc):
                        crashed.append(cell)
                    else:
                        yield failed_row(cell, f"{type(exc).__name__}: {' '.join(str(exc).split())}")
            if crashed:  # every cell still running went down with the pool
                in_flight = crashed + [cell for cell, _ in running.values()]
                running.clear()
                executor = None
                if len(in_flight) == 1:
                    yield failed_row(in_flight[0], _DIED)
                else:
                    suspects.extend(reversed(in_flight))
                continue
            now = time.monotonic()
            late = [f for f, (cell, start) in running.items()
                    if cell.timeout is not None and now - start > cell.timeout]
            if late:
                executor.shutdown(wait=False, kill_workers=True)
                executor = None
                for future in late:
                    cell, _ = running.pop(future)
                    yield failed_row(cell, f"TimeoutError: the cell ran longer than its timeout of "
                                     f"{cell.timeout:g} s")
                pending.extend(cell for cell, _ in running.values())
                running.clear()
    finally:
        if running and executor is not None:  # interrupted: leave no cell running
            executor.shutdown(wait=False, kill_workers=True)


_DIED = ("WorkerDied: the cell's worker process died (a crash, the OOM killer, or os._exit); "
         "run it alone to see why")


def _ready() -> bool:
    from . import cell  # noqa: F401 - what every cell imports (numpy, scikit-learn, novelty)

    return True


def _pool_broken(exc: BaseException) -> bool:
    return isinstance(exc, BrokenExecutor)


@contextlib.contextmanager
def dask_client(scheduler: str | None, jobs: int):
    """A client of the scheduler at ``scheduler``, or of a new local cluster on loopback."""
    try:
        # optional dependency (dask), imported only for the dask backend
        from distributed import Client, LocalCluster
    except ImportError:
        raise BackendError(
            "The dask backend needs dask.distributed: pip install 'novelty-habituation[dask]'."
        ) from None
    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise BackendError(f"Cannot reach the Dask scheduler at {scheduler}: {exc}") from None
        with client:
            yield client
        return
    with LocalCluster(n_workers=max(jobs, 1), threads_per_worker=1, processes=True,
                      host="127.0.0.1", dashboard_address=None) as cluster, Client(cluster) as client:
        yield client


def run_dask(cells: Iterable[Cell], jobs: int = 2, scheduler: str | None = None,
             client=None) -> Iterator[tuple]:
    """Cells as Dask futures, on the cluster at ``scheduler`` (or a local one)."""
    cells = list(cells)
    if not cells:
        return
    with contextlib.ExitStack() as stack:
        if client is None:
            client = stack.enter_context(dask_client(scheduler, jobs))
        # optional dependency (dask), imported only for the dask backend
        from distributed import as_completed

        futures = client.map(_run_with_deadline, cells, pure=False,
                             key=[f"novelty-cell-{c.id}" for c in cells])
        cell_of = dict(zip((f.key for f in futures), cells))
        try:
            for future in as_completed(futures):
                try:
                    yield future.result()
                except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: the worker died, repeatedly
                    yield failed_row(cell_of[future.key],
                                     f"{type(exc).__name__}: {' '.join(str(exc).split())}")
        finally:
            client.cancel(futures)


def _run_with_deadline(cell: Cell) -> tuple:
    """``run_cell`` on a Dask worker, given up on after the cell's timeout.

    The cell runs in a thread, which cannot be stopped: past the timeout it is
    recorded as failed and left to finish on its own.
    """
    if cell.timeout is None:
        return run_cell_in_worker(cell)

    result: list = []
    thread = threading.Thread(target=lambda: result.append(run_cell_in_worker(cell)), daemon=True)
    thread.start()
    thread.join(cell.timeout)
    if result:
        return result[0]
    return failed_row(cell, f"TimeoutError: the cell ran longer than its timeout of {cell.timeout:g} s "
                      "(on Dask it runs on in its worker)")


_RUNNERS = {"serial": run_serial, "joblib": run_joblib, "dask": run_dask}


def execute(cells: Iterable[Cell], backend: str = "serial", jobs: int = 1,
            scheduler: str | None = None, client=None) -> Iterator[tuple]:
    """Run ``cells`` on ``backend``; yield ``(row, arrays)`` as cells finish."""
    if backend not in _RUNNERS:
        raise BackendError(f"Unknown backend {backend!r}; expected one of {', '.join(BACKENDS)}.")
    if backend == "dask":
        return _isolated(run_dask(cells, jobs, scheduler, client=client))
    return _isolated(_RUNNERS[backend](cells, jobs, scheduler))


def _isolated(rows: Iterator[tuple]) -> Iterator[tuple]:
    # workers start lazily (at a first submit, after a crash), so for as long as cells run
    with isolated_children():
        yield from rows
