"""Learning compiled: the clusterer's and the synapse's state handed to their pair's driver.

:func:`learner` answers, for a (clusterer, synapse) pair, a function that
gives what :func:`novelty.filter.learn_stream` gives, state and all, or None
when the pair runs the reference: a component whose own class declares no
kernel (``_kernel``, see :class:`~novelty._component.KernelSpec`), state not
in the declared layout, kernels disabled or unavailable.

The driver works on the components' own arrays while it adds no unit; when
an input needs room it stops, and :func:`run` copies the state into arrays
with spare rows (at most doubling them, so few are wasted) and resumes,
until the batch is done; then the arrays, trimmed, are the components'
again.

A call of a few scans (the robot's, or a calibrating filter's one at a
time) must cost little besides the driver: what :func:`ready` checked of a
pair's arrays, and the pair's driver, are remembered while the components
hold the same arrays; parameters are read on every call
(:func:`.params.pack`).
"""

from __future__ import annotations

import operator
import weakref
from functools import partial
from typing import Callable

import numpy as np

from ._pairwise import pairwise_plan
from .compiling import disabled
from .drivers import driver_for
from .handover import handing_over
from .params import arrays_of, attribute, counters_of, getter, nested_ready, pack, spec_of

__all__ = ["compiled_for", "learner", "run", "ready"]

_plans: dict[int, np.ndarray] = {}


def _plan(n_features: int) -> np.ndarray:
    plan = _plans.get(n_features)
    if plan is None:
        plan = _plans[n_features] = pairwise_plan(n_features)
    return plan


def _c(a: np.ndarray) -> np.ndarray:
    """``a`` as the driver's signature wants it: C-contiguous, writable float64 (copied if not)."""
    if a.dtype == np.float64:
        flags = a.flags
        if flags.c_contiguous and flags.writeable:
            return a
    return np.array(a, dtype=np.float64, order="C")


def _plain(a) -> bool:
    flags = a.flags
    return flags.c_contiguous and flags.writeable


def ready(clusterer, synapse) -> tuple | None:
    """The pair's specs and state, if both declare kernels and hold their state as declared.

    The checks of the state arrays are remembered for the pair
    (:class:`_Checked`): while the components hold the very arrays checked
    last time, of the same shapes and types, only that is verified.
    """
    c_spec, s_spec = spec_of(clusterer), spec_of(synapse)
    if c_spec is None or s_spec is None or not nested_ready(clusterer, c_spec):
        return None
    readers = _readers(type(clusterer), type(synapse), c_spec, s_spec)
    try:
        arrays = readers[0](clusterer) + readers[1](synapse)
    except AttributeError:
        return None
    checked = _last_checked(clusterer)
    if (checked is not None and checked.synapse is synapse and checked.specs == (c_spec, s_spec)
            and all(map(operator.is_, arrays, checked.arrays))
            and tuple(map(_LAYOUT, arrays)) == checked.layout):
        counters = counters_of(clusterer, c_spec)
        return None if counters is None else checked.parts + (counters,)
    state = _check(clusterer, synapse, c_spec, s_spec)
    if state is not None:
        _remember(clusterer, synapse, state, arrays)
    return state


def _check(clusterer, synapse, c_spec, s_spec) -> tuple | None:
    W = getattr(clusterer, "weights_", None)
    if type(W) is not np.ndarray or W.ndim != 2 or W.dtype != np.float64 or W.shape[0] == 0:
        return None
    n = W.shape[0]
    c_arrays = arrays_of(clusterer, c_spec, n)
    s_arrays = arrays_of(synapse, s_spec, n)
    counters = counters_of(clusterer, c_spec)
    if c_arrays is None or not s_arrays or counters is None:
        return None
    if s_arrays[0] is not getattr(synapse, "efficacy_", None) or any(
            a.dtype != np.float64 or a.ndim != 1 for a in s_arrays):
        return None  # the drivers read the efficacy as the first of the synapse's arrays
    return c_spec, s_spec, W, c_arrays, s_arrays, counters


#: what identifies an array's layout for the checks: its shape and type
_LAYOUT = operator.attrgetter("shape", "dtype")
_reader_cache: dict[tuple, tuple] = {}


def _readers(c_class: type, s_class: type, c_spec, s_spec) -> tuple:
    """Functions reading, in one call each, the clusterer's weights and state arrays and the
    synapse's state arrays (as tuples)."""
    key = (c_class, s_class)
    known = _reader_cache.get(key)
    if known is None or known[0] is not c_spec or known[1] is not s_spec:
        known = _reader_cache[key] = (c_spec, s_spec, getter(("weights_",) + c_spec.arrays),
                                      getter(s_spec.arrays))
    return known[2:]


class _Checked:
    """A pair's state arrays as :func:`ready` last checked them (kept per clusterer, weakly)."""

    __slots__ = ("synapse", "specs", "arrays", "layout", "parts", "compiled")


_checked: "weakref.WeakKeyDictionary[object, _Checked]" = weakref.WeakKeyDictionary()


def _last_checked(clusterer) -> _Checked | None:
    try:
        return _checked.get(clusterer)
    except TypeError:  # a clusterer that cannot be weakly referenced or hashed
        return None


def _remember(clusterer, synapse, state: tuple, arrays: tuple) -> None:
    checked = _Checked()
    checked.synapse = synapse
    checked.specs = state[:2]
    checked.arrays = arrays
    checked.layout = tuple(map(_LAYOUT, arrays))
    checked.parts = state[:5]
    checked.compiled = None  # the pair's driver for these arrays' types, once asked for
    try:
        _checked[clusterer] = checked
    except TypeError:
        pass


def _roomy(arrays, square, n: int, cap: int) -> list:
    out = []
    for a, sq in zip(arrays, square):
        b = np.zeros((cap, cap) if sq else (cap,) + a.shape[1:], dtype=a.dtype)
        if sq:
            b[:n, :n] = a[:n, :n]
        else:
            b[:n] = a[:n]
        out.append(b)
    return out


def _trimmed(arrays, square, n: int) -> list:
    return [np.ascontiguousarray(a[:n, :n] if sq else a[:n]) if a.shape[0] != n else a
            for a, sq in zip(arrays, square)]


def _set(component, names, arrays) -> None:
    for name, a in zip(names, arrays):
        owner_path, _, leaf = name.rpartition(".")
        owner = attribute(component, owner_path) if owner_path else component
        if getattr(owner, leaf) is not a:
            setattr(owner, leaf, a)


def run(clusterer, synapse, X: np.ndarray, dt: np.ndarray, stimulus: float,
        distances: np.ndarray | None = None, winners: np.ndarray | None = None,
        state: tuple | None = None, compiled=None) -> np.ndarray:
    """Learn the rows of ``X`` compiled; return their novelty (the winners' efficacies).

    ``distances`` and ``winners`` (int64), if given, receive each row's squared
    distance to its winner and the winner's row (at the time of the row).
    ``state`` and ``compiled``: what :func:`ready` and :func:`compiled_for` answer
    for the pair now, if known.
    """
    state = state or ready(clusterer, synapse)
    c_spec, s_spec, W, c_arrays, s_arrays, counters = state
    drive = (compiled or compiled_for(clusterer, synapse, state)).module.drive
    X, dt = _c(X), _c(dt)
    m = X.shape[0]
    novelty = np.empty(m)
    d = np.empty(m) if distances is None else distances
    rows = np.empty(m, dtype=np.int64) if winners is None else winners
    plan = _plan(X.shape[1])
    cp, sp = pack(clusterer), pack(synapse)
    stimulus = float(stimulus)
    n = n_before = W.shape[0]
    # in place on the components' own arrays when they are plain; else on copies
    copies = not (_plain(W) and all(map(_plain, c_arrays)) and all(map(_plain, s_arrays)))
    start = 0
    stopped = False  # the driver stopped for want of room
    while True:
        if copies:  # with room for what stopped the driver, if it stopped
            cap = n + max(1, min(m - start, max(n, 16))) if stopped else n
            c_square = [name in c_spec.square for name in c_spec.arrays]
            (W,) = _roomy([W], [False], n, cap)
            c_arrays = _roomy(c_arrays, c_square, n, cap)
            s_arrays = _roomy(s_arrays, [False] * len(s_arrays), n, cap)
        if start:
            done, n = drive(W, tuple(c_arrays), counters, cp, tuple(s_arrays), sp, X[start:],
                            dt[start:], stimulus, n, plan, rows[start:], novelty[start:], d[start:])
        else:
            done, n = drive(W, tuple(c_arrays), counters, cp, tuple(s_arrays), sp, X, dt, stimulus,
                            n, plan, rows, novelty, d)
        start += done
        if start >= m:
            break
        copies = stopped = True
    if copies or n != n_before:  # the arrays, trimmed, are the components' again
        c_square = [name in c_spec.square for name in c_spec.arrays]
        (W,) = _trimmed([W], [False], n)
        clusterer.weights_ = W
        _set(clusterer, c_spec.arrays, _trimmed(c_arrays, c_square, n))
        _set(synapse, s_spec.arrays, _trimmed(s_arrays, [False] * len(s_arrays), n))
    for name, value in zip(c_spec.counters, counters.tolist()):
        setattr(clusterer, name, value)
    return novelty


def compiled_for(clusterer, synapse, state: tuple | None = None):
    """The pair's driver (a :class:`.compiling.Compiled`), or None when it runs the reference."""
    state = state or ready(clusterer, synapse)
    if state is None:
        return None
    checked = _last_checked(clusterer)
    mine = checked is not None and checked.parts[3] is state[3] and checked.parts[4] is state[4]
    if mine and checked.compiled is not None:  # the arrays checked last time: the same types
        return checked.compiled
    c_spec, s_spec, W, c_arrays, s_arrays, _ = state
    try:
        compiled = driver_for(c_spec.steps, s_spec.steps, type(clusterer), type(synapse), W,
                              c_arrays, s_arrays)
    except (OSError, ImportError):  # no folder to write the driver to; a steps module missing
        return None
    if mine:
        checked.compiled = compiled
    return compiled


def learner(clusterer, synapse, reference: Callable) -> Callable | None:
    """A function ``(clusterer, synapse, X, dt, stimulus, distances=None) -> novelty``, or None.

    ``reference`` is the readable loop (``learn_stream``), which runs while the
    pair's driver compiles (see :mod:`.handover`).
    """
    if disabled():
        return None
    state = ready(clusterer, synapse)
    compiled = compiled_for(clusterer, synapse, state)
    if compiled is None:
        return None
    if compiled.module is not None or compiled.get() is not None:
        return partial(run, state=state, compiled=compiled)
    return handing_over(compiled, run, reference) if compiled.compiling else None
