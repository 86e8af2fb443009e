"""A fitted pair's compiled loop: the engine a habituating filter owns.

An :class:`Engine` is built in one place (:func:`engine_for`) for a
(clusterer, synapse) pair whose classes both declare compiled steps
(``_kernel``, a :class:`~novelty._component.KernelSpec`), and holds what the
pair's driver needs: the two declarations, functions that read the state
arrays, parameters and counters in one call each, the parameter records
packed from them (:func:`.params.pack`: a named field per parameter), and the driver (a :class:`.compiling.Compiled`). The filter
keeps one in ``_engine``; ``set_params`` and ``load`` drop it and the next
call builds a new one.

The components stay the owners of their state (``weights_``, ``efficacy_``
are theirs, and may be replaced or changed by anyone), so on every call the
engine reads the arrays and parameters it is about to hand over and compares
them with those it checked last time: the very same arrays, of the same
shapes and types, are used as they are; anything else is checked again
(the reference runs when the state is not in the declared layout); the
parameter records are packed again when a value changed.

The driver works on the components' own arrays while it adds no unit; when
an input needs room it stops, and :meth:`Engine.learn` copies the state into
arrays with spare rows (at most doubling them, so few are wasted) and
resumes, until the batch is done; then the arrays, trimmed, are the
components' again.
"""

from __future__ import annotations

import operator
from typing import Callable

import numpy as np

from .compiling import disabled
from .drivers import driver_for
from .handover import handing_over
from .params import arrays_of, attribute, getter, nested_ready, pack, param_names, spec_of

__all__ = ["Engine", "engine_for"]

#: what identifies an array's layout for the checks: its shape and type
_LAYOUT = operator.attrgetter("shape", "dtype")


def engine_for(clusterer, synapse) -> "Engine | None":
    """The pair's engine, or None when it learns by the reference: a part whose own class
    declares no compiled steps (or a nested part other steps than its owner drives it with),
    kernels disabled (``NOVELTY_NO_KERNELS``)."""
    c_spec, s_spec = spec_of(clusterer), spec_of(synapse)
    if c_spec is None or s_spec is None or not nested_ready(clusterer, c_spec) or disabled():
        return None
    return Engine(clusterer, synapse, c_spec, s_spec)


def _values_getter(component, spec) -> Callable:
    """The values of the parameters the steps read, nested components' included, in one tuple."""
    own = getter(param_names(component))
    nested = [(name, _values_getter(getattr(component, name), spec_of(getattr(component, name))))
              for name, _ in spec.nested]
    if not nested:
        return own
    return lambda c: own(c) + tuple(v for name, read in nested for v in read(getattr(c, name)))


class Engine:
    """The compiled loop of one (clusterer, synapse) pair (module docstring)."""

    def __init__(self, clusterer, synapse, c_spec, s_spec):
        self.clusterer, self.synapse = clusterer, synapse
        self.c_spec, self.s_spec = c_spec, s_spec
        self._read_c = getter(("weights_",) + c_spec.arrays)
        self._read_s = getter(s_spec.arrays)
        self._read_counters = getter(c_spec.counters)
        self._read_cv = _values_getter(clusterer, c_spec)
        self._read_sv = getter(param_names(synapse))
        self._arrays = self._layout = None  # the arrays checked last, and their layout
        self._compiled = None  # the driver for those arrays' types
        self._cv = self._sv = None  # the parameter values packed last, with their types
        self._cp = self._sp = None  # and the bytes of the records packed from them

    # ------------------------------------------------------------- the state
    def state(self) -> tuple | None:
        """``(W, c_arrays, s_arrays, counters)`` as the driver takes them now, or None when
        the state is not in the declared layout."""
        c, s = self.clusterer, self.synapse
        if self.c_spec.nested and not nested_ready(c, self.c_spec):
            return None
        try:
            c_read, s_read = self._read_c(c), self._read_s(s)
            counters = self._read_counters(c)
        except AttributeError:
            return None
        arrays = c_read + s_read
        if not (self._arrays is not None and all(map(operator.is_, arrays, self._arrays))
                and tuple(map(_LAYOUT, arrays)) == self._layout):
            if not self._check(c_read, s_read):
                self._arrays = None
                return None
            types = tuple(map(_LAYOUT, arrays))
            if self._layout is None or [t[1] for t in types] != [t[1] for t in self._layout]:
                self._compiled = None  # other types: another driver (or none yet)
            self._arrays, self._layout = arrays, types
        try:
            counter_array = np.array(counters, dtype=np.int64)
        except (TypeError, ValueError, OverflowError):
            return None
        return c_read[0], c_read[1:], s_read, counter_array

    def _check(self, c_read, s_read) -> bool:
        W = c_read[0]
        if type(W) is not np.ndarray or W.ndim != 2 or W.dtype != np.float64 or W.shape[0] == 0:
            return False
        n = W.shape[0]
        if arrays_of(self.clusterer, self.c_spec, n) is None or not s_read:
            return False
        if arrays_of(self.synapse, self.s_spec, n) is None:
            return False
        # the drivers read the efficacy as the first of the synapse's arrays
        return s_read[0] is getattr(self.synapse, "efficacy_", None) and all(
            a.dtype == np.float64 and a.ndim == 1 for a in s_read)

    def params(self) -> tuple:
        """The clusterer's and the synapse's parameters as the driver takes them: the bytes of
        their records (``c_record``, ``s_record``: :func:`.params.pack`), which the driver
        views as the records again; packed again if a value changed. (numba types a plain
        byte array at once; a structured array by a slower path, 0.1 us a call each.)"""
        cv, sv = self._read_cv(self.clusterer), self._read_sv(self.synapse)
        if cv != self._cv or tuple(map(type, cv)) != self._cv_types:
            record = pack(self.clusterer)
            if self.c_record is not None and record.dtype != self.c_record.dtype:
                self._compiled = None  # another nested part: another record, another driver
            self.c_record, self._cp = record, record.view(np.uint8)
            self._cv, self._cv_types = cv, tuple(map(type, cv))
        if sv != self._sv or tuple(map(type, sv)) != self._sv_types:
            self.s_record = pack(self.synapse)
            self._sp = self.s_record.view(np.uint8)
            self._sv, self._sv_types = sv, tuple(map(type, sv))
        return self._cp, self._sp

    _cv_types = _sv_types = None
    #: the parameter records packed last (:func:`.params.pack`): ``c_record["learning_rate"]``
    c_record = s_record = None

    # ------------------------------------------------------------ the driver
    def compiled(self, state: tuple | None = None):
        """The driver for the state's array types (a :class:`.compiling.Compiled`), or None."""
        state = state or self.state()
        if state is None:
            return None
        if self._compiled is None:
            W, c_arrays, s_arrays, _ = state
            try:
                self.params()
                self._compiled = driver_for(self.c_spec.steps, self.s_spec.steps,
                                            type(self.clusterer), type(self.synapse), W, c_arrays,
                                            s_arrays, self.c_record.dtype, self.s_record.dtype)
            except (OSError, ImportError):  # no folder to write the driver to; a steps module missing
                return None
        return self._compiled

    def learner(self, reference: Callable) -> Callable | None:
        """A function ``(clusterer, synapse, X, dt, stimulus, distances=None) -> novelty`` that
        learns compiled (or by ``reference`` block by block while the driver compiles, see
        :mod:`.handover`), or None when the pair runs the reference now."""
        if disabled():
            return None
        state = self.state()
        compiled = self.compiled(state)
        if compiled is None:
            return None
        if compiled.module is not None or compiled.get() is not None:
            return self._learn
        return handing_over(compiled, self._learn, reference) if compiled.compiling else None

    def _learn(self, clusterer, synapse, X, dt, stimulus, distances=None, winners=None):
        return self.learn(X, dt, stimulus, distances, winners)

    def run(self, reference: Callable, X: np.ndarray, dt: np.ndarray, stimulus: float,
            distances: np.ndarray | None = None) -> np.ndarray:
        """Learn the rows of ``X``: compiled when the driver is ready, else by ``reference``
        (``learn_stream``; block by block while the driver compiles). The state is read once."""
        state = None if disabled() else self.state()
        compiled = None if state is None else self.compiled(state)
        if compiled is not None:
            if compiled.module is not None or compiled.get() is not None:
                return self.learn(X, dt, stimulus, distances, state=state)
            if compiled.compiling:
                return handing_over(compiled, self._learn, reference)(
                    self.clusterer, self.synapse, X, dt, stimulus, distances=distances)
        return reference(self.clusterer, self.synapse, X, dt, stimulus, distances=distances)

    def learn(self, X: np.ndarray, dt: np.ndarray, stimulus: float,
              distances: np.ndarray | None = None, winners: np.ndarray | None = None,
              state: tuple | None = None) -> np.ndarray:
        """Learn the rows of ``X`` compiled; return their novelty (the winners' efficacies).

        ``distances`` and ``winners`` (int64), if given, receive each row's squared
        distance to its winner and the winner's row (at the time of the row). ``state``:
        what :meth:`state` answers now, if known.
        """
        state = state or self.state()
        W, c_arrays, s_arrays, counters = state
        drive = self.compiled(state).module.drive
        cp, sp = self.params()
        X, dt = _c(X), _c(dt)
        m = X.shape[0]
        novelty = np.empty(m)
        d = np.empty(m) if distances is None else distances
        rows = np.empty(m, dtype=np.int64) if winners is None else winners
        stimulus = float(stimulus)
        n = n_before = W.shape[0]
        # in place on the components' own arrays when they are plain; else on copies
        copies = not (_plain(W) and all(map(_plain, c_arrays)) and all(map(_plain, s_arrays)))
        c_square = [name in self.c_spec.square for name in self.c_spec.arrays]
        s_square = [False] * len(s_arrays)
        start = 0
        stopped = False  # the driver stopped for want of room
        while True:
            if copies:  # with room for what stopped the driver, if it stopped
                cap = n + max(1, min(m - start, max(n, 16))) if stopped else n
                (W,) = _roomy([W], [False], n, cap)
                c_arrays = _roomy(c_arrays, c_square, n, cap)
                s_arrays = _roomy(s_arrays, s_square, n, cap)
            done, n = drive(W, tuple(c_arrays), counters, cp, tuple(s_arrays), sp, X[start:],
                            dt[start:], stimulus, n, rows[start:], novelty[start:], d[start:])
            start += done
            if start >= m:
                break
            copies = stopped = True
        if copies or n != n_before:  # the arrays, trimmed, are the components' again
            (W,) = _trimmed([W], [False], n)
            self.clusterer.weights_ = W
            _set(self.clusterer, self.c_spec.arrays, _trimmed(c_arrays, c_square, n))
            _set(self.synapse, self.s_spec.arrays, _trimmed(s_arrays, s_square, n))
        for name, value in zip(self.c_spec.counters, counters.tolist()):
            setattr(self.clusterer, name, value)
        return novelty

    def __reduce__(self):
        # an engine is scratch: a copy or a pickle of its filter builds its own
        return _dropped, ()


def _dropped():
    return None


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
