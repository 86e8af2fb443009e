"""The arithmetic of the habituating filter: one engine interface, two implementations.

A filter holds one engine (:mod:`.interface`) for its fitted (clusterer,
synapse) pair and never asks which kind it is:

- :class:`~.reference.ReferenceEngine` (:mod:`.reference`), numpy: the
  readable loop, the specification;
- :class:`~.engine.CompiledEngine` (:mod:`.engine`), numba: the same
  arithmetic, equal to the reference bit for bit (the arithmetic is the
  same, distances included, :mod:`novelty.distances`; ``tests/_kernels``
  checks every registered pair).

Which one, and why, is decided in one place (:mod:`.choice`); what an engine
reads is checked in one place (:mod:`.state`). The compiled machinery, one
job per module: :mod:`.compiling` (one background compiler, readiness,
numba's disk cache), :mod:`.children` (the compiling children and the tricks'
self-check), :mod:`.tricks` (whether the drivers use :mod:`._uncounted` and
:mod:`._lanes`, which lean on numba's internals, decided by a self-check),
:mod:`.params` (state and parameters read from the components' declarations),
:mod:`.drivers` (the one loop, generated per pair), :mod:`.handover` (from
the reference to the driver mid-stream),
:mod:`._distances` (the project's summation order), :mod:`.scoring` with
:mod:`._nearest` (each scan's nearest unit, on threads:
``NOVELTY_NUM_THREADS``, default: the usable cores).

``NOVELTY_NO_KERNELS`` set to a non-empty value other than ``0`` runs the
reference (:func:`reference_loops` sets it for a block of code).
"""

from __future__ import annotations

import contextlib
import os
from typing import Callable

from . import choice, compiling
from .choice import choose, engine_for, why_not_learning, why_not_scoring
from .engine import CompiledEngine, driver_of
from .interface import Engine
from .reference import ReferenceEngine, learn_stream
from .scoring import score

__all__ = ["Engine", "ReferenceEngine", "CompiledEngine", "engine_for", "choose", "learn_stream",
           "scorer", "kernels_enabled", "wait", "reference_loops"]

#: the nearest-unit kernels (:data:`.choice.NEAREST`), by the name benchmarks know
_NEAREST = choice.NEAREST


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
    pair is given, else the scoring kernels and every driver asked for so far.

    Returns the module waited for last, or None when kernels are unavailable.
    """
    if clusterer is not None:
        if why_not_learning(clusterer, synapse) is not None:
            return None
        try:
            return driver_of(clusterer, synapse).wait(timeout)
        except (OSError, ImportError):
            return None
    for module in compiling.live():
        if module is not choice.NEAREST:
            module.wait(timeout)
    return choice.NEAREST.wait(timeout)


def scorer(clusterer, synapse) -> Callable | None:
    """The compiled batch scoring of a fitted pair, ``(clusterer, synapse, X, winners=None,
    distances=None) -> efficacy``, or None when it does not run compiled (now).

    The novelty is the efficacy of each scan's nearest unit; ``winners`` (int64) and
    ``distances``, if given, receive each scan's winning row and its squared distance, as
    ``match`` computes them (:mod:`.scoring`).
    """
    nearest = choice.NEAREST
    if why_not_scoring(clusterer) is not None or (nearest.module is None and nearest.get() is None):
        return None
    return _score


def _score(net, syn, X, winners=None, distances=None):
    return score(choice.NEAREST.module, net.weights_, syn.efficacy_, X, winners, distances)
