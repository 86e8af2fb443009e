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
  other than ``0`` (for comparisons and debugging).

numba is imported here only on the first call that wants a kernel, so
``import novelty`` does not pay for it; compiled code is cached on disk
(``cache=True``), so later processes load it instead of compiling again.
"""

from __future__ import annotations

import os
import warnings
from typing import Callable

import numpy as np

__all__ = ["learner", "scorer", "kernels_enabled"]

_module = None  # the compiled module, once loaded
_failed = False  # numba missing or broken: warned once, never retried


def kernels_enabled() -> bool:
    """Whether compiled kernels may be used (numba importable, not disabled)."""
    return _load() is not None


def _load():
    global _module, _failed
    if _module is not None:
        return _module
    if _failed or os.environ.get("NOVELTY_NO_KERNELS", "") not in ("", "0"):
        return None
    try:
        from . import _som_stanley
    except Exception as exc:  # ImportError, or numba/LLVM failing to compile or load
        _failed = True
        warnings.warn(
            f"novelty: compiled kernels are unavailable ({type(exc).__name__}: {exc}); "
            "using the reference numpy loops, which give the same results more slowly.",
            RuntimeWarning,
            stacklevel=3,
        )
        return None
    _module = _som_stanley
    return _module


def _plain(a: np.ndarray, ndim: int) -> bool:
    # The kernels update state in place: it must be an owned-layout float64 array.
    return (
        type(a) is np.ndarray
        and a.ndim == ndim
        and a.dtype == np.float64
        and a.flags.c_contiguous
        and a.flags.writeable
    )


_DECAY_CODES = {"constant": 0, "linear": 1, "asymptotic": 2}


def _som_ready(clusterer) -> bool:
    from ..clusterers.som import SOM

    W = getattr(clusterer, "weights_", None)
    return (
        type(clusterer) is SOM
        and _plain(W, 2)
        and W.shape[0] == clusterer.n_rows * clusterer.n_columns
        and clusterer.decay in _DECAY_CODES
        and hasattr(clusterer, "_table_radius")
    )


def _stanley_ready(synapse, n_units: int) -> bool:
    from ..habituation.stanley import StanleySynapse

    y = getattr(synapse, "efficacy_", None)
    return (
        type(synapse) is StanleySynapse
        and _plain(y, 1)
        and y.shape[0] == n_units
        and synapse.method in ("euler", "exact")
        and synapse.others in ("hold", "forget")
    )


def learner(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X, dt, stimulus) -> novelty`` equal to ``learn_stream``, or None."""
    if not (_som_ready(clusterer) and _stanley_ready(synapse, clusterer.weights_.shape[0])):
        return None
    if _load() is None:
        return None
    return _learn_som_stanley


def scorer(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X) -> novelty`` equal to ``efficacy_[winners(X)]``, or None.

    Scoring only reads the efficacies, so any synapse model with a plain
    ``efficacy_`` array will do.
    """
    y = getattr(synapse, "efficacy_", None)
    if not (_som_ready(clusterer) and _plain(y, 1) and y.shape[0] == clusterer.weights_.shape[0]):
        return None
    if _load() is None:
        return None
    return _score_som


_plans: dict[int, np.ndarray] = {}


def _plan(n_features: int) -> np.ndarray:
    plan = _plans.get(n_features)
    if plan is None:
        plan = _plans[n_features] = _module.pairwise_plan(n_features)
    return plan


def _learn_som_stanley(som, syn, X: np.ndarray, dt: np.ndarray, stimulus: float,
                       winners: np.ndarray | None = None) -> np.ndarray:
    # ``winners`` (int64, one per row) receives the winning rows, for tests
    n = X.shape[0]
    novelty = np.empty(n)
    tau_f = syn.tau_neighbour if syn.tau_forget is None else syn.tau_forget
    radius, t = _module.som_stanley_stream(
        som.weights_, syn.efficacy_, np.ascontiguousarray(X, dtype=np.float64),
        np.ascontiguousarray(dt, dtype=np.float64),
        np.empty(n, dtype=np.int64) if winners is None else winners, novelty, np.empty(n),
        _plan(X.shape[1]), True,
        int(som.n_columns), int(som._table_radius), int(som.n_updates_),
        _DECAY_CODES[som.decay], float(som.learning_rate), float(som.learning_rate_final),
        float(som.radius), float(som.radius_final), int(som.decay_steps),
        syn.method == "exact", syn.others == "forget",
        float(syn.tau_winner), float(syn.tau_neighbour), float(tau_f),
        float(syn.alpha), float(syn.y0), float(stimulus),
    )
    som.n_updates_ = int(t)
    if radius != som._table_radius:
        # SOM.adapt rebuilds its neighbour table whenever the scheduled radius changes
        som._rebuild_scratch()
    return novelty


#: rows scored per kernel call: bounds the scratch (winners, distances) to 1 MB a thread
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


def _score_part(som, y, X, out, plan) -> None:
    for lo in range(0, X.shape[0], _SCORE_CHUNK):
        block = X[lo : lo + _SCORE_CHUNK]
        m = block.shape[0]
        _module.som_stanley_stream(
            som.weights_, y, block, _NO_DT, np.empty(m, dtype=np.int64), out[lo : lo + m],
            np.empty(m), plan, False, int(som.n_columns), 0, 0,
            0, 0.0, 0.0, 0.0, 0.0, 1, False, False, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0,
        )


def _score_som(som, syn, X: np.ndarray) -> np.ndarray:
    global _pool
    X = np.ascontiguousarray(X, dtype=np.float64)
    n = X.shape[0]
    out = np.empty(n)
    plan = _plan(X.shape[1])
    threads = min(_threads(), n // _SCORE_CHUNK)
    if threads <= 1:
        _score_part(som, syn.efficacy_, X, out, plan)
        return out
    # The kernel releases the GIL (nogil): contiguous parts score in parallel.
    if _pool is None or _pool._max_workers < threads:
        from concurrent.futures import ThreadPoolExecutor

        _pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="novelty-score")
    bounds = np.linspace(0, n, threads + 1).astype(int)
    jobs = [_pool.submit(_score_part, som, syn.efficacy_, X[a:b], out[a:b], plan)
            for a, b in zip(bounds[:-1], bounds[1:])]
    for job in jobs:
        job.result()
    return out
