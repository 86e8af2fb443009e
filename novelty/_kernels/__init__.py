"""Compiled fast paths for the habituating filter, for every (clusterer, synapse) pair.

The readable numpy code (:func:`novelty.filter.learn_stream`, ``match``,
``winners``) is the reference; a kernel is an optimisation that must give the
same winners, weights and efficacies (bit for bit: the arithmetic is the
same, distances included, :mod:`novelty.distances`; ``tests/_kernels`` checks
every registered pair). A filter owns the :class:`~.engine.Engine` of its
fitted pair (:func:`engine_for`), and asks it, and :func:`scorer`, for a
kernel on every call, falling back to the reference when they answer ``None``:

- a component whose own class declares no kernel (a plugin without compiled
  steps, a subclass that may change the arithmetic): :func:`path` says which
  path a pair runs, and why;
- the state is not in the layout the component declares;
- numba is missing or failed to compile (a ``RuntimeWarning``, once);
- the environment variable ``NOVELTY_NO_KERNELS`` is set to a non-empty value
  other than ``0`` (for comparisons; :func:`reference_loops` sets it for a
  block of code).

The machinery, one job per module: :mod:`.compiling` (one background
compiler, readiness, numba's disk cache), :mod:`.children` (the compiling
children and the tricks' self-check), :mod:`.tricks` (whether the drivers use
:mod:`._uncounted` and :mod:`._lanes`, which lean on numba's internals, decided
by a self-check), :mod:`.params` (state and parameters read from the
components' declarations), :mod:`.drivers` (the one loop, generated per
pair), :mod:`.engine` (a pair's state and parameters handed to its driver,
the state grown),
:mod:`.handover` (from the reference to the kernel mid-stream),
:mod:`._distances` (the project's summation order, :mod:`novelty.distances`). Batch
scoring is :mod:`.scoring`: a float32 pre-filter with exact re-checks, on
threads (``NOVELTY_NUM_THREADS``, default: the usable cores).
"""

from __future__ import annotations

import contextlib
import os
from typing import Callable

import numpy as np

from .._component import declares
from . import compiling
from .compiling import Compiled, disabled
from .engine import Engine, engine_for
from .params import nested_ready, spec_of
from .scoring import score

__all__ = ["Engine", "engine_for", "learner", "scorer", "scoring_kernels", "kernels_enabled", "wait",
           "path", "reference_loops"]

_NEAREST = Compiled("novelty._kernels._nearest")  # batch scoring (see .scoring)


def learner(clusterer, synapse, reference: Callable) -> Callable | None:
    """A function ``(clusterer, synapse, X, dt, stimulus, distances=None) -> novelty``, or None.

    The function gives what ``reference`` (``learn_stream``) gives, state and all. (A new
    engine each call: a filter keeps its own, see :func:`engine_for`.)
    """
    engine = engine_for(clusterer, synapse)
    return None if engine is None else engine.learner(reference)


def path(clusterer, synapse) -> str:
    """Which loop a pair learns by: ``"compiled"``, or ``"reference (<why>)"``.

    Asks nothing of numba: a pair whose kernel is still compiling is
    ``"compiled"`` (it runs the reference until then, with the same results).
    """
    for part in (clusterer, synapse):
        if spec_of(part) is None:
            return f"reference ({type(part).__name__} declares no compiled steps)"
    if not nested_ready(clusterer, spec_of(clusterer)):
        return f"reference ({type(clusterer).__name__}'s parts declare other steps)"
    if disabled():
        return "reference (NOVELTY_NO_KERNELS)"
    if hasattr(clusterer, "weights_"):
        compiled = engine_for(clusterer, synapse).compiled()
        if compiled is None:
            return "reference (state not in the declared layout)"
        if compiled.failed or compiled.error is not None:
            return f"reference (kernels unavailable: {compiled.error})"
    return "compiled"


@contextlib.contextmanager
def reference_loops():
    """Run the readable numpy loops instead of the kernels inside the block (benchmarks)."""
    saved = os.environ.get("NOVELTY_NO_KERNELS")
    os.environ["NOVELTY_NO_KERNELS"] = "1"
    try:
        yield
    finally:
        if saved is None:
            del os.environ["NOVELTY_NO_KERNELS"]
        else:
            os.environ["NOVELTY_NO_KERNELS"] = saved


def kernels_enabled() -> bool:
    """Whether compiled kernels are in use (waits for them to be compiled)."""
    return wait() is not None


def wait(clusterer=None, synapse=None, timeout: float | None = None):
    """Compile (or load) kernels now and block until done: the pair's driver when a fitted
    pair is given, else the scoring kernel and every driver asked for so far.

    Returns the module waited for last, or None when kernels are unavailable.
    """
    if clusterer is not None:
        engine = engine_for(clusterer, synapse)
        compiled = None if engine is None else engine.compiled()
        return None if compiled is None else compiled.wait(timeout)
    for compiled in compiling.live():
        if compiled is not _NEAREST:
            compiled.wait(timeout)
    return _NEAREST.wait(timeout)


def _plain(a, ndim: int) -> bool:
    # The kernels read state in place: it must be a plain float64 array.
    if type(a) is not np.ndarray or a.ndim != ndim or a.dtype != np.float64:
        return False
    flags = a.flags
    return flags.c_contiguous and flags.writeable


def scorer(clusterer, synapse) -> Callable | None:
    """A function ``(clusterer, synapse, X, winners=None, distances=None) -> novelty``, or None.

    The novelty is ``efficacy_[winners(X)]``; ``winners`` (int64) and
    ``distances``, if given, receive each row's winning row and its squared
    distance, as ``match`` computes them (:mod:`.scoring`).

    Scoring only reads the weights and the efficacies, so any synapse model
    with a plain ``efficacy_`` array will do; the clusterer's class declares
    the capability ``"nearest-unit"`` (its winner is the first unit of least
    squared distance, :func:`novelty._component.declares`).
    """
    if not declares(clusterer, "nearest-unit"):
        return None
    W, y = getattr(clusterer, "weights_", None), getattr(synapse, "efficacy_", None)
    # the weights in any layout (a learning engine holds them transposed: its weights_ is a
    # strided view, which scoring copies into rows once a call)
    if not (type(W) is np.ndarray and W.ndim == 2 and W.dtype == np.float64
            and _plain(y, 1) and y.shape[0] == W.shape[0]):
        return None
    if disabled() or (_NEAREST.module is None and _NEAREST.get() is None):
        return None
    return _score


def scoring_kernels():
    """The compiled batch-scoring module (:mod:`._nearest`) when it is loaded already, else
    None (kernels disabled, or not compiled yet: :func:`scorer` starts that)."""
    return None if disabled() else _NEAREST.module


def _score(net, syn, X, winners=None, distances=None):
    return score(_NEAREST.module, net.weights_, syn.efficacy_, X, winners, distances)
