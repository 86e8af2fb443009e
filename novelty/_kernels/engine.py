"""The compiled engine: the filter's loop in numba, holding the fitted pair's state.

The engine interface (:mod:`.interface`) implemented by compiled code, the
same arithmetic as the reference (:mod:`.reference`), bit for bit. Learning
runs the pair's driver (:mod:`.drivers`: one generated loop composing the
clusterer's and the synapse's steps) when both parts declare steps; scoring
runs the nearest-unit kernels (:mod:`._nearest`, through :mod:`.scoring`)
when the clusterer declares ``"nearest-unit"``. A half that cannot compile
is the reference's (the engine is a :class:`~.reference.ReferenceEngine`
too): which, and why, :func:`novelty._kernels.choice.choose` decides and
passes in.

**Who sees the state.** Learning compiled, the engine holds the state in
arrays of its own, with room for more units: the parts' attributes
(``weights_``, ``efficacy_``, the declared arrays and counters) always show
it, the arrays as read-only views of the first ``n`` units of the engine's
(:func:`novelty._component.held_by_engine`), the counters written back after
every call; the driver writes the engine's own arrays. The engine holds the weights
transposed, ``WT`` (features, capacity), as the driver works on them (the
distances to every unit vectorise over the units): ``weights_`` is the view
``WT[:, :n].T``, so it is not C-contiguous (numpy reads and writes it as any
array; :func:`numpy.ascontiguousarray` copies it where a caller needs rows in
memory). Keeping the weights transposed between calls, instead of transposing
them in and out on every call, saves a share of every single-scan call
(docs/guide/performance.md). Giving the parts views counts as changes, which the engine
takes as seen; the counters are written back through ``vars``, uncounted.

**Growth.** The driver stops when an input needs a unit it has no room for;
:meth:`CompiledEngine.learn` then moves the state into buffers with more rows
(at least doubling, so few are wasted and few moves happen) and resumes.

One module although just over 300 lines: holding the state, driving it and
growing it are one job on the same arrays.
"""

from __future__ import annotations

import functools
from typing import Callable

import numpy as np

from .._component import engine_writes
from .drivers import driver_for
from .handover import learn_handing_over
from .interface import flat
from .params import attribute, getter, pack, spec_of
from .reference import ReferenceEngine
from .scoring import score as _score_batch

__all__ = ["CompiledEngine", "driver_of", "whole_vectors", "VECTOR"]


def driver_of(clusterer, synapse, records=None):
    """The pair's driver (a :class:`.compiling.Compiled`) for the types of its state and
    parameter records (one per pair and types, per process; not compiled yet, perhaps);
    ``records``: the parts' records (:func:`.params.pack`), if the caller packed them."""
    c_spec, s_spec = spec_of(clusterer), spec_of(synapse)
    c_record, s_record = records if records is not None else (pack(clusterer), pack(synapse))
    W = clusterer.weights_
    return driver_for(c_spec.steps, s_spec.steps, type(clusterer), type(synapse), W,
                      [attribute(clusterer, name) for name in c_spec.arrays],
                      [attribute(synapse, name) for name in s_spec.arrays],
                      c_record.dtype, s_record.dtype)


class CompiledEngine(ReferenceEngine):
    """The engine interface (:mod:`.interface`) in compiled code (module docstring).

    Each method of the interface is defined here and runs the compiled half that is ready,
    else the reference's: ``learn`` and ``learn_one`` by the driver once it drives
    (:attr:`driving`; while it compiles, ``learn`` hands over from the reference,
    :mod:`.handover`), ``score``, ``nearest`` and ``score_one`` by the nearest-unit kernels
    when the clusterer declares them.

    Parameters
    ----------
    clusterer, synapse : the fitted parts, their state checked (:mod:`.state`).
    driver : Compiled or None
        The pair's driver, loaded: learning is compiled. None: the reference learns.
    compiling : Compiled or None
        The pair's driver while it compiles in the background: the reference learns
        meanwhile, block by block, and hands over when it is ready (:mod:`.handover`).
    scoring : module or None
        The nearest-unit kernels (:mod:`._nearest`), loaded: scoring is compiled.
    pending : tuple
        The kernels still compiling (:attr:`~.interface.Engine.pending`).
    """

    why = "compiled"
    #: the driver's ``drive`` and ``score_one`` once it drives (:meth:`start_driving`): until
    #: then the reference learns (handing over when ``_compiling`` is ready)
    _drive = _score_one = None

    def __init__(self, clusterer, synapse, driver=None, compiling=None, scoring=None, pending=(),
                 records=None):
        super().__init__(clusterer, synapse, "compiled", pending)
        self.c_spec, self.s_spec = spec_of(clusterer), spec_of(synapse)
        if driver is not None or compiling is not None:
            self._read_c = getter(("weights_",) + self.c_spec.arrays)
            self._read_s = getter(self.s_spec.arrays)
            self._read_counters = getter(self.c_spec.counters)
            self._c_square = tuple(name in self.c_spec.square for name in self.c_spec.arrays)
            self._counter_names = self.c_spec.counters
            # the clusterer's counters written back into its attributes in one statement
            self._write_counters = _counter_writer(self.c_spec.counters)
            # a single scan's arguments, kept between calls
            self._winner1 = np.empty(1, dtype=np.int64)
            self._one = (np.ones(1),)  # the driver's arguments for one scan, around stimulus and n
            self._out1 = (self._winner1, self.novelty1, self.distance1)
        self._compiling = compiling
        self._kernels = scoring
        if driver is not None:
            self.start_driving(driver, records)

    def start_driving(self, driver, records=None) -> None:
        """Learn by ``driver`` (loaded) from now on, on the state as the parts hold it now
        (``records``: the parts' records packed just now, by :func:`.choice.choose`)."""
        self.hold(records)
        self._drive, self._score_one = driver.module.drive, driver.module.score_one
        self._compiling = None

    # ------------------------------------------------------------- the state
    def hold(self, records=None) -> None:
        """Read the parts' state into the engine's own arrays, with room to a whole number of
        vectors (nobody else holds them, so nobody can make them read-only or strided), and
        give the parts views of them."""
        c, s = self.clusterer, self.synapse
        c_read, s_read = self._read_c(c), self._read_s(s)
        n = c_read[0].shape[0]
        capacity = whole_vectors(n)
        self._WT = _roomy_columns(c_read[0].T, n, capacity)
        self._c_arrays = [_roomy(a, sq, n, capacity) for a, sq in zip(c_read[1:], self._c_square)]
        self._s_arrays = [_roomy(a, False, n, capacity) for a in s_read]
        self.n, self.capacity = n, capacity
        self._counters = np.array(self._read_counters(c), dtype=np.int64).reshape(-1)
        # the parameters as the driver takes them: the bytes of their records (.params.pack),
        # which the driver views as the records again (numba types a plain byte array at once; a
        # structured array by a slower path, at every call)
        self.c_record, self.s_record = records if records is not None else (pack(c), pack(s))
        self._head = (self._WT, *self._c_arrays, self._counters, self.c_record.view(np.uint8),
                      *self._s_arrays, self.s_record.view(np.uint8))
        self._arrays = (self._WT, *self._c_arrays, *self._s_arrays)
        self._show(n)

    def take_parameters(self) -> bool:
        """The clusterer's record packed again, into the bytes the driver reads (its fields,
        and so its dtype, are the same unless a value's type changed: then False)."""
        if not hasattr(self, "c_record"):  # not driving yet: the record is packed when it starts
            return True
        record = pack(self.clusterer)
        if record.dtype != self.c_record.dtype:
            return False
        self.c_record[...] = record
        return True

    def value_arrays(self) -> list:
        """The arrays :meth:`check_values` sums: the engine's own buffers in place of the parts'
        views of them (contiguous, one dot each: faster than einsum on the transposed ``weights_``
        view), and any other float state
        as the parts hold it. The room past the units is zero or a unit the driver moved (a
        value that passed): it adds nothing a check would refuse."""
        buffers = {id(b): b for b in getattr(self, "_arrays", ())}
        arrays = [buffers.pop(id(a.base), a) if a.base is not None else a for _, a in self.state_arrays()]
        return [flat(a) for a in arrays]

    def _show(self, n: int) -> None:
        """Give the parts views of the first ``n`` units of the engine's arrays (counted as
        changes, which the engine takes as seen)."""
        with engine_writes(self.parts):
            _put(self.clusterer, "weights_", self._WT[:, :n].T)
            for name, a, square in zip(self.c_spec.arrays, self._c_arrays, self._c_square):
                _put(self.clusterer, name, a[:n, :n] if square else a[:n])
            for name, a in zip(self.s_spec.arrays, self._s_arrays):
                _put(self.synapse, name, a[:n])
        self._shown = n
        self.seen()

    def _grow(self, capacity: int) -> None:
        """Move the state into arrays with room for ``capacity`` units (to a whole vector)."""
        n = self.n
        capacity = whole_vectors(capacity)
        self._WT = _roomy_columns(self._WT, n, capacity)
        self._c_arrays = [_roomy(a, sq, n, capacity) for a, sq in zip(self._c_arrays, self._c_square)]
        self._s_arrays = [_roomy(a, False, n, capacity) for a in self._s_arrays]
        self.capacity = capacity
        self._shown = -1  # the parts' views are of the old arrays
        head = self._head
        k = len(self._c_arrays)
        self._head = (self._WT, *self._c_arrays, *head[1 + k:3 + k], *self._s_arrays, head[-1])
        self._arrays = (self._WT, *self._c_arrays, *self._s_arrays)

    def _finish(self, n: int) -> None:
        """After the driver: the parts see the units and counters it left."""
        self.n = n
        if n != self._shown:
            self._show(n)
        if self._counter_names:
            self._write_counters(vars(self.clusterer), self._counters.tolist())

    @property
    def driving(self) -> bool:
        """Whether the pair's driver learns (else the reference, handing over to the driver
        once it is compiled when it was compiling)."""
        return self._drive is not None

    # ------------------------------------------------------------- learning
    def learn(self, X, dt, stimulus, distances=None, winners=None):
        """The interface's ``learn``, by the driver once it drives: while it compiles, the
        reference learns block by block and hands over when it is ready (:mod:`.handover`);
        without a driver, the reference. ``winners`` (int64, the driver's only), if given,
        receives each row's winner (its row at the time)."""
        if self._drive is None:
            if self._compiling is not None:
                return learn_handing_over(self, self._compiling, X, dt, stimulus, distances)
            return ReferenceEngine.learn(self, X, dt, stimulus, distances)
        self.check_scans(X)
        self.check_values()
        X, dt = _c(X), _c(dt)
        m = X.shape[0]
        novelty = np.empty(m)
        d = np.empty(m) if distances is None else distances
        rows = np.empty(m, dtype=np.int64) if winners is None else winners
        stimulus = float(stimulus)
        n = self.n
        start = 0
        while True:
            done, n = self._drive(*self._head, X[start:], dt[start:], stimulus, n, rows[start:],
                                  novelty[start:], d[start:], False)
            start += done
            if start >= m:
                break
            # no room for the unit the next input adds: at least double, at most one per input
            self.n = n
            self._grow(n + max(1, min(m - start, max(n, 16))))
        self._finish(n)
        return novelty

    def learn_one(self, x, stimulus) -> bool:
        """The interface's ``learn_one``, by the driver once it drives (else the reference's),
        which checks the scan first: as many features as the units have, and a sum of squares
        within the norm bound with a margin (``novelty._validation.scans.CLEARED``, far wider
        than rounding), so that NaN, infinity and too large values all fail it (False, nothing
        learned); and the state's values, which may have been written in place since the last
        call (False when one is not finite: the general path's :meth:`check_values` then names
        it, as the reference's does)."""
        if self._drive is None:
            return ReferenceEngine.learn_one(self, x, stimulus)
        X = x[None, :]
        while True:
            done, n = self._drive(*self._head, X, *self._one, stimulus, self.n, *self._out1, True)
            if done:
                break
            self._grow(self.n + max(self.n, 16))  # no room for the unit it adds
        if done < 0:
            return False
        self.n = n
        if n != self._shown:
            self._show(n)
        if self._counter_names:
            self._write_counters(vars(self.clusterer), self._counters.tolist())
        return True

    # -------------------------------------------------------------- scoring
    def nearest(self, X):
        """The interface's ``nearest``, by the nearest-unit kernels when the clusterer
        declares them (else the reference's)."""
        if self._kernels is None:
            return ReferenceEngine.nearest(self, X)
        rows, distances, _ = self._score(X)
        return rows, distances

    def score(self, X):
        """The interface's ``score``, by the nearest-unit kernels when the clusterer declares
        them (else the reference's)."""
        if self._kernels is None:
            return ReferenceEngine.score(self, X)
        return self._score(X)

    def score_one(self, x) -> bool:
        """The interface's ``score_one``: with the nearest-unit kernels and the driver, against
        the weights as learning holds them (``WT``), checked first as :meth:`learn_one` checks
        it, the state's values and the scan, by the driver module's ``score_one`` (one call: its
        checks cost less than a second call from Python would); else the reference's, a batch
        of one by :meth:`score`."""
        if self._kernels is None or self._score_one is None:
            return ReferenceEngine.score_one(self, x)
        return self._score_one(*self._arrays, self.n, x, self.scored1) == 0

    def _score(self, X):
        self.check_scans(X)
        self.check_values()
        m = X.shape[0]
        rows, distances = np.empty(m, dtype=np.int64), np.empty(m)
        flags = X.flags  # the driver takes a contiguous, writable scan as it is
        if m <= FEW and self._score_one is not None and flags.c_contiguous and flags.writeable:
            efficacy = self._score_few(X, rows, distances)
            if efficacy is not None:
                return rows, distances, efficacy
        efficacy = _score_batch(self._kernels, self.clusterer.weights_, self.synapse.efficacy_, X,
                                rows, distances)
        return rows, distances, efficacy

    def _score_few(self, X, rows, distances):
        """A short batch (at most :data:`FEW` scans, checked) scan by scan by the driver's
        ``score_one`` against the weights as learning holds them: the batch kernel copies the
        weights into rows first (``weights_`` is a transposed view of them), over half of a
        call that scores one scan. The same winners and distances (both exact, the first of the
        least), or None when the driver's own check refuses a scan (a unit that passed
        :meth:`check_values` but not the driver's cheaper bound): then the batch kernel."""
        efficacy = np.empty(X.shape[0])
        arrays, n, out = self._arrays, self.n, self.scored1
        for i, x in enumerate(X):
            if self._score_one(*arrays, n, x, out):
                return None
            efficacy[i], distances[i], rows[i] = out
        return efficacy


def _c(a: np.ndarray) -> np.ndarray:
    """``a`` as the driver's signature wants it: C-contiguous, writable float64 (copied if not)."""
    if a.dtype == np.float64:
        flags = a.flags
        if flags.c_contiguous and flags.writeable:
            return a
    return np.array(a, dtype=np.float64, order="C")


def _roomy(a: np.ndarray, square: bool, n: int, capacity: int) -> np.ndarray:
    """The first ``n`` units of ``a`` in a new array with room for ``capacity``, zero."""
    b = np.zeros((capacity, capacity) if square else (capacity,) + a.shape[1:], dtype=a.dtype)
    if square:
        b[:n, :n] = a[:n, :n]
    else:
        b[:n] = a[:n]
    return b


@functools.lru_cache(maxsize=64)  # compiling one is slow next to a short stream call
def _counter_writer(names: tuple[str, ...]) -> Callable:
    """``write(d, values)``: ``d[name] = value`` for the counters' names and values, as one
    unpacking assignment compiled for these names (as :func:`collections.namedtuple` compiles
    its class): faster for a single scan than ``d.update(zip(names, values))``. The names are
    quoted as string literals (``repr``), so any name is only ever a key."""
    if not names:
        return lambda d, values: None
    targets = "".join(f"d[{name!r}], " for name in names)
    namespace: dict = {}
    exec(f"def write(d, values):\n    {targets}= values\n", namespace)
    return namespace["write"]


#: the units of a vector in the distance loops (``novelty._kernels._distances.VECTOR``, which
#: imports numba, as this module must not: a test keeps the two equal)
VECTOR = 8
#: the longest batch :meth:`CompiledEngine._score` scores scan by scan (the batch kernel's fixed
#: cost is more than one or two scans scored one by one, less than four:
#: docs/guide/performance.md)
FEW = 2


def whole_vectors(capacity: int) -> int:
    """``capacity`` rounded up to whole vectors: the distance loops then run over whole
    vectors of columns, the room past the units zero (finite: no slow path on garbage), with
    no scalar remainder (a remainder taken one unit at a time was slower than one more
    vector: docs/guide/performance.md)."""
    return capacity + (-capacity) % VECTOR


def _roomy_columns(WT: np.ndarray, n: int, capacity: int) -> np.ndarray:
    """The first ``n`` units (columns) of the transposed weights in a new array with room for
    ``capacity``, zero."""
    b = np.zeros((WT.shape[0], capacity), dtype=WT.dtype)
    b[:, :n] = WT[:, :n]
    return b


def _put(component, name: str, value) -> None:
    """Set ``component.<name>`` (dotted: a nested component's)."""
    owner_path, _, leaf = name.rpartition(".")
    setattr(attribute(component, owner_path) if owner_path else component, leaf, value)
