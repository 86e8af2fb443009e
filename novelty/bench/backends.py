"""Where cells run: in this process, in joblib worker processes, or on Dask.

Each backend is a generator ``execute(cells) -> iterator of (row, arrays)``
yielding every cell's result as soon as it finishes (in any order), so the
caller can record it at once. Cells are pure functions
(:func:`novelty.bench.cell.run_cell`), hence every backend gives the same
numbers for the same suite.
"""

from __future__ import annotations

import contextlib
from typing import Iterable, Iterator

from .cell import run_cell
from .suite import Cell

__all__ = ["BACKENDS", "execute", "BackendError"]

BACKENDS = ("serial", "joblib", "dask")


class BackendError(RuntimeError):
    """A backend that cannot start (missing package, unreachable scheduler)."""


def run_serial(cells: Iterable[Cell], jobs: int = 1, scheduler: str | None = None) -> Iterator[tuple]:
    for cell in cells:
        yield run_cell(cell)


def run_joblib(cells: Iterable[Cell], jobs: int = 2, scheduler: str | None = None) -> Iterator[tuple]:
    """Processes on this machine (joblib's loky backend), ``jobs`` at a time."""
    from joblib import Parallel, delayed

    cells = list(cells)
    if not cells:
        return
    parallel = Parallel(n_jobs=jobs, return_as="generator_unordered", batch_size=1)
    yield from parallel(delayed(run_cell)(cell) for cell in cells)


@contextlib.contextmanager
def dask_client(scheduler: str | None, jobs: int):
    """A client of the scheduler at ``scheduler``, or of a new local cluster on loopback."""
    try:
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
        from distributed import as_completed

        futures = client.map(run_cell, cells, pure=False, key=[f"novelty-cell-{c.id}" for c in cells])
        try:
            for future in as_completed(futures):
                yield future.result()
        finally:
            client.cancel(futures)


_RUNNERS = {"serial": run_serial, "joblib": run_joblib, "dask": run_dask}


def execute(cells: Iterable[Cell], backend: str = "serial", jobs: int = 1,
            scheduler: str | None = None, client=None) -> Iterator[tuple]:
    """Run ``cells`` on ``backend``; yield ``(row, arrays)`` as cells finish."""
    if backend not in _RUNNERS:
        raise BackendError(f"Unknown backend {backend!r}; expected one of {', '.join(BACKENDS)}.")
    if backend == "dask":
        return run_dask(cells, jobs, scheduler, client=client)
    return _RUNNERS[backend](cells, jobs, scheduler)
