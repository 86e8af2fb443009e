"""Compiled fast paths for the habituating filter, chosen per (clusterer, synapse) pair.

The readable numpy code (:func:`novelty.filter.learn_stream`, ``match``,
``winners``) is the reference; a kernel here is an optimisation that must
give the same winners, weights and efficacies bit for bit
(``tests/test_kernels.py`` checks it). The filter asks :func:`learner` and
:func:`scorer` for a kernel on every call and falls back to the reference
when they answer ``None``:

- the pair has no kernel (only ``SOM`` + ``StanleySynapse`` has one; exact
  types, since a subclass may change the arithmetic);
- the state is not in the plain layout the kernel writes to in place;
- numba is missing or failed to compile (a ``RuntimeWarning``, once);
- the environment variable ``NOVELTY_NO_KERNELS`` is set to a non-empty value
  other than ``0`` when the first kernel is asked for (for comparisons).

Compiling in the background. numba is imported only when the first kernel
is asked for, so ``import novelty`` does not pay for it. Compiling the kernel
takes seconds the first time; numba caches the machine code on disk
(``cache=True``, in ``NUMBA_CACHE_DIR`` when set) and later processes load it
in a fraction of a second. So that no call waits for the compiler, it runs
in a background thread: meanwhile learning runs the reference loop in small
blocks and hands over to the kernel, mid-stream, as soon as it is ready
(the two give identical states, so the hand-over is invisible in the
results). The thread is not a daemon: a process that ends early waits for it,
so that the cache gets written. :func:`wait` blocks until the kernels are
ready (benchmarks, tests). Batch scoring splits large batches across threads
(``NOVELTY_NUM_THREADS``, default: the usable cores); the kernel releases the
GIL.
"""

from __future__ import annotations

import os
import threading
import warnings
from typing import Callable

import numpy as np

from ..clusterers.som import SOM
from ..habituation.stanley import StanleySynapse

__all__ = ["learner", "scorer", "kernels_enabled", "wait"]

_module = None  # the compiled module, once ready
_failed = False  # numba missing, broken or disabled: never retried
_thread: threading.Thread | None = None
_error: BaseException | None = None  # raised in the thread, warned about in the caller's


def kernels_enabled() -> bool:
    """Whether compiled kernels are in use (waits for them to be compiled)."""
    return wait() is not None


def wait(timeout: float | None = None):
    """Compile or load the kernels now and block until done; the module or None."""
    _load()
    if _thread is not None:
        _thread.join(timeout)
    return _load()


def _compile() -> None:
    global _module, _error
    try:
        from . import _som_stanley  # compiles, or loads from numba's cache

        _module = _som_stanley
    except BaseException as exc:  # ImportError, or numba/LLVM failing to compile or load
        _error = exc


def _load():
    """The compiled module if ready; else start compiling it (once) and return None."""
    global _failed, _thread
    if _module is not None:
        return _module
    if _failed:
        return None
    if _error is not None:
        _failed = True
        warnings.warn(
            f"novelty: compiled kernels are unavailable ({type(_error).__name__}: {_error}); "
            "using the reference numpy loops, which give the same results more slowly.",
            RuntimeWarning,
            stacklevel=4,
        )
        return None
    if _thread is None:
        if os.environ.get("NOVELTY_NO_KERNELS", "") not in ("", "0"):
            _failed = True
            return None
        _thread = threading.Thread(target=_compile, name="novelty-compile-kernels")
        _thread.start()
    return None


def _compiling() -> bool:
    return _module is None and not _failed and _thread is not None


def _plain(a, ndim: int) -> bool:
    # The kernels update state in place: it must be a plain, writable float64 array.
    if type(a) is not np.ndarray or a.ndim != ndim or a.dtype != np.float64:
        return False
    flags = a.flags
    return flags.c_contiguous and flags.writeable


def _c(a: np.ndarray) -> np.ndarray:
    """``a`` as the kernel's signature wants it: C-contiguous, writable float64 (copied if not)."""
    if a.dtype == np.float64:
        flags = a.flags
        if flags.c_contiguous and flags.writeable:
            return a
    return np.array(a, dtype=np.float64, order="C")


def _som_ready(som, y) -> bool:
    W = getattr(som, "weights_", None)
    return (
        _plain(W, 2)
        and _plain(y, 1)
        and y.shape[0] == W.shape[0]
        and hasattr(som, "_table_radius")
    )


def learner(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X, dt, stimulus) -> novelty`` equal to ``learn_stream``, or None."""
    if type(clusterer) is not SOM or type(synapse) is not StanleySynapse:
        return None
    if not _som_ready(clusterer, getattr(synapse, "efficacy_", None)):
        return None
    if _module is None and _load() is None:
        return _learn_while_compiling if _compiling() else None
    return _learn_som_stanley


def scorer(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X) -> novelty`` equal to ``efficacy_[winners(X)]``, or None.

    Scoring only reads the efficacies, so any synapse model with a plain
    ``efficacy_`` array will do.
    """
    if type(clusterer) is not SOM or not _som_ready(clusterer, getattr(synapse, "efficacy_", None)):
        return None
    if _module is None and _load() is None:
        return None
    return _score_som


# ---------------------------------------------------------------- parameters
_DECAY_CODES = {"constant": 0, "linear": 1, "asymptotic": 2}
_plans: dict[int, np.ndarray] = {}
_params: dict[tuple, np.ndarray] = {}


def _plan(n_features: int) -> np.ndarray:
    plan = _plans.get(n_features)
    if plan is None:
        plan = _plans[n_features] = _module.pairwise_plan(n_features)
    return plan


def _som_stanley_params(som, syn, stimulus: float) -> np.ndarray | None:
    """The kernel's ``params`` vector (see ``_som_stanley.PARAMS``), or None if out of its scope.

    Parameters may change between calls (``set_params``), so they are read
    every time; the vector is cached by value because building it costs
    more than looking it up.
    """
    key = (som.n_rows, som.n_columns, som.decay, som.learning_rate, som.learning_rate_final,
           som.radius, som.radius_final, som.decay_steps, syn.method, syn.others,
           syn.tau_winner, syn.tau_neighbour, syn.tau_forget, syn.alpha, syn.y0, stimulus)
    params = _params.get(key)
    if params is None:
        if som.decay not in _DECAY_CODES or syn.method not in ("euler", "exact") \
                or syn.others not in ("hold", "forget"):
            return None
        tau_f = syn.tau_neighbour if syn.tau_forget is None else syn.tau_forget
        values = {
            "n_columns": som.n_columns, "decay": _DECAY_CODES[som.decay],
            "learning_rate": som.learning_rate, "learning_rate_final": som.learning_rate_final,
            "radius": som.radius, "radius_final": som.radius_final,
            "decay_steps": som.decay_steps, "exact": syn.method == "exact",
            "forget": syn.others == "forget", "tau_winner": syn.tau_winner,
            "tau_neighbour": syn.tau_neighbour, "tau_forget": tau_f, "alpha": syn.alpha,
            "y0": syn.y0, "stimulus": stimulus,
        }
        params = np.array([float(values[name]) for name in _module.PARAMS])
        if len(_params) > 256:  # a parameter sweep: do not grow without bound
            _params.clear()
        _params[key] = params
    return params


# ------------------------------------------------------------------ learning
def _learn_som_stanley(som, syn, X: np.ndarray, dt: np.ndarray, stimulus: float,
                       winners: np.ndarray | None = None) -> np.ndarray:
    # ``winners`` (int64, one per row) receives the winning rows, for tests.
    params = _som_stanley_params(som, syn, stimulus)
    if params is None or som.n_rows * som.n_columns != som.weights_.shape[0]:
        from ..filter import learn_stream

        return learn_stream(som, syn, X, dt, stimulus)
    n = X.shape[0]
    novelty = np.empty(n)
    radius, t = _module.som_stanley_stream(
        som.weights_, syn.efficacy_, _c(X), _c(dt),
        np.empty(n, dtype=np.int64) if winners is None else winners, novelty, np.empty(n),
        _plan(X.shape[1]), params, True, som._table_radius, som.n_updates_,
    )
    som.n_updates_ = t
    if radius != som._table_radius:
        # SOM.adapt rebuilds its neighbour table whenever the scheduled radius changes
        som._rebuild_scratch()
    return novelty


#: scans learned by the reference between two looks at the compiler thread
_HANDOVER_BLOCK = 256


def _learn_while_compiling(som, syn, X, dt, stimulus, winners=None):
    """The reference loop, block by block, until the kernel is ready; then the kernel."""
    from ..filter import learn_stream

    if winners is not None:  # only tests ask for winners, and they wait for the kernel
        raise ValueError("winners are only reported by the compiled kernel")
    novelty = np.empty(X.shape[0])
    start = 0
    while start < X.shape[0]:
        if _module is not None or _load() is not None:
            novelty[start:] = _learn_som_stanley(som, syn, X[start:], dt[start:], stimulus)
            break
        stop = start + _HANDOVER_BLOCK
        novelty[start:stop] = learn_stream(som, syn, X[start:stop], dt[start:stop], stimulus)
        start = stop
    return novelty


# ------------------------------------------------------------------- scoring
#: rows per kernel call when scoring: bounds the scratch (winners, distances)
#: to 1 MB a thread, whatever the batch
_SCORE_CHUNK = 65536
_NO_DT = np.empty(0)
_pool = None


def _threads() -> int:
    value = os.environ.get("NOVELTY_NUM_THREADS", "")
    if value.isdigit() and int(value) > 0:
        return int(value)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _score_params(som) -> np.ndarray:
    key = ("score", som.n_columns)  # scoring reads no other parameter
    params = _params.get(key)
    if params is None:
        params = _params[key] = np.ones(len(_module.PARAMS))
        params[0] = som.n_columns
    return params


def _score_part(som, y, X, out, plan, params) -> None:
    for lo in range(0, X.shape[0], _SCORE_CHUNK):
        block = _c(X[lo : lo + _SCORE_CHUNK])  # a read-only batch is copied block by block
        m = block.shape[0]
        _module.som_stanley_stream(som.weights_, y, block, _NO_DT, np.empty(m, dtype=np.int64),
                                   out[lo : lo + m], np.empty(m), plan, params, False, 0, 0)


def _score_som(som, syn, X: np.ndarray) -> np.ndarray:
    global _pool
    n = X.shape[0]
    out = np.empty(n)
    plan = _plan(X.shape[1])
    params = _score_params(som)
    if n < 2 * _SCORE_CHUNK or _threads() == 1:
        _score_part(som, syn.efficacy_, X, out, plan, params)
        return out
    # The kernel releases the GIL (nogil): contiguous parts score in parallel.
    threads = min(_threads(), n // _SCORE_CHUNK)
    if _pool is None or _pool._max_workers < threads:
        from concurrent.futures import ThreadPoolExecutor

        _pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="novelty-score")
    bounds = np.linspace(0, n, threads + 1).astype(int)
    jobs = [_pool.submit(_score_part, som, syn.efficacy_, X[a:b], out[a:b], plan, params)
            for a, b in zip(bounds[:-1], bounds[1:])]
    for job in jobs:
        job.result()
    return out
