"""Batch scoring without learning: each scan's nearest unit and its efficacy, on every core.

:func:`score` gives what the reference gives (``Clusterer.match`` scan by
scan: the winner is the first unit of least squared distance, the distance
is :func:`novelty.distances.squared_distances` at the winner; the novelty its efficacy),
bit for bit, through the compiled :func:`._nearest.nearest` (a float32
pre-filter with exact float64 re-checks; its docstring derives the bound).
The batch is cut into chunks of :data:`CHUNK` scans (bounding the kernel's
scratch whatever the batch) that threads, the caller's among them, take one
at a time and score in parallel: the kernel releases the GIL. The number of threads is ``NOVELTY_NUM_THREADS`` when set
to a positive integer, else the cores this process may use. Scans are
independent, so the result does not depend on the threads.

No numba here: the compiled module is passed in by :mod:`novelty._kernels`,
which compiles and loads it.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np


__all__ = ["score", "threads"]

#: scans per kernel call: from two chunks on, threads share the work (8192: a chunk is
#: short enough to share a batch of 200,000 scans evenly: docs/guide/performance.md)
CHUNK = 8192

_lock = threading.Lock()
_pool: ThreadPoolExecutor | None = None
_pool_size = 0


def threads() -> int:
    """Threads that score a large batch: ``NOVELTY_NUM_THREADS``, else the usable cores."""
    value = os.environ.get("NOVELTY_NUM_THREADS", "")
    if value.isdigit() and int(value) > 0:
        return int(value)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _executor(n_threads: int) -> ThreadPoolExecutor:
    """A pool of at least ``n_threads`` workers, kept between calls."""
    global _pool, _pool_size
    with _lock:
        if _pool is None or _pool_size < n_threads:
            # a smaller pool still in use finishes its work; its idle threads end
            # when it is garbage collected
            _pool = ThreadPoolExecutor(max_workers=n_threads, thread_name_prefix="novelty-score")
            _pool_size = n_threads
        return _pool


def _contiguous(a: np.ndarray) -> np.ndarray:
    """``a`` as the kernel's signature wants it: C-contiguous, writable float64 (copied if not)."""
    if a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable:
        return a
    return np.array(a, dtype=np.float64, order="C")


def score(module, W: np.ndarray, y: np.ndarray, X: np.ndarray,
          winners: np.ndarray | None = None, distances: np.ndarray | None = None) -> np.ndarray:
    """The efficacies ``y`` of the nearest rows of ``W`` to the rows of ``X``.

    ``module`` is the compiled :mod:`._nearest`; ``W`` (float64, copied into rows if it is
    not C-contiguous) and ``y`` are read, never written. ``winners`` (int64) and ``distances``,
    if given, receive each scan's winning row and its squared distance.
    """
    if W.ndim != 2 or y.shape != (W.shape[0],) or X.ndim != 2 or X.shape[1] != W.shape[1]:
        # the kernel indexes by these shapes: refused before it reads past an array
        raise ValueError(f"Scoring needs weights (units, features), one efficacy per unit and scans "
                         f"of the weights' features; got {W.shape}, {y.shape} and {X.shape}.")
    n = X.shape[0]
    out = np.empty(n)
    rows = np.empty(n, dtype=np.int64) if winners is None else winners
    dist = np.empty(n) if distances is None else distances
    if rows.shape != (n,) or rows.dtype != np.int64 or dist.shape != (n,) or dist.dtype != np.float64:
        raise ValueError("Scoring writes one int64 winner and one float64 distance per scan.")
    kernel = module.nearest
    W, y = _contiguous(W), _contiguous(y)

    n_chunks = -(-n // CHUNK)
    # one chunk (score_one, a short batch): no threads, and no asking how many (an
    # environment read and a system call, a third of a score_one's cost)
    n_threads = 1 if n_chunks < 2 else min(threads(), n_chunks)
    if n_threads < 2:
        for a in range(0, n, CHUNK):
            _chunk(kernel, W, y, X, a, min(a + CHUNK, n), rows, out, dist)
        return out
    # Chunks are handed out one at a time, as threads come for them: a thread
    # slowed by another process on its core scores fewer (a fixed share each
    # would make the whole call wait for the slowest).
    starts = iter(range(0, n, CHUNK))  # next() on it is atomic (the GIL)

    def work() -> None:
        for a in starts:
            _chunk(kernel, W, y, X, a, min(a + CHUNK, n), rows, out, dist)

    pool = _executor(n_threads - 1)
    jobs = [pool.submit(work) for _ in range(n_threads - 1)]
    work()  # this thread takes chunks too
    for job in jobs:
        job.result()
    return out


def _chunk(kernel, W, y, X, a, b, rows, out, dist) -> None:
    # a read-only or strided batch is copied chunk by chunk
    kernel(W, y, _contiguous(X[a:b]), rows[a:b], out[a:b], dist[a:b])
