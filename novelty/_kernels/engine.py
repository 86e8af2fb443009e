"""A fitted pair's compiled loop: the engine a habituating filter owns, holding the pair's state.

An :class:`Engine` is built in one place (:func:`engine_for`) for a
(clusterer, synapse) pair whose classes both declare compiled steps
(``_kernel``, a :class:`~novelty._component.KernelSpec`). It holds what the
pair's driver needs: the state arrays (with spare rows for a growing
network), the counters, the parameter records packed from the components
(:func:`.params.pack`: a named field per parameter), the driver (a
:class:`.compiling.Compiled`) and a single scan's arguments. The filter keeps
one in ``_engine``; ``set_params`` and ``load`` drop it and the next call
builds a new one.

**Who sees the state.** The components' attributes (``weights_``,
``efficacy_``, the declared arrays and counters) always show the current
state: the arrays are views of the first ``n`` units of the engine's own
arrays; the counters are written back after every call. Writing into those
arrays in place is seen by the next call, which reads them in place. The
engine holds the weights transposed, ``WT`` (features, capacity), as the
driver works on them (the distances to every unit vectorise over the units):
``weights_`` is the view ``WT[:, :n].T``, so it is not C-contiguous (numpy
reads and writes it as any array; :func:`numpy.ascontiguousarray` copies it
where a caller needs rows in memory). Keeping the weights transposed between
calls, instead of transposing them in and out on every call, saves a single
scan about 1 us (100 units of 16 features).

**Noticing a change.** Setting an attribute of a component counts a change
(:meth:`novelty._component.Component.__setattr__`), so the engine compares
one count per component with those it saw when it last read them: equal,
and its arrays, counters and packed parameters are still the components';
different (an array replaced, a parameter or counter set, by anyone), and
it reads and checks them again, into arrays of its own (the reference runs
when the state is not in the declared layout). Giving the components views
of its arrays counts too, and the engine takes those counts as seen: another
engine of the same components reads them again before it works on arrays
they no longer show. The counters are written back through ``vars``,
uncounted.

**Growth.** The driver stops when an input needs a unit it has no room
for; :meth:`Engine.learn` then moves the state into buffers with more rows
(at least doubling, so few are wasted and few moves happen) and resumes.
"""

from __future__ import annotations

import functools
import operator
from typing import Callable

import numpy as np

from .._component import declares
from .compiling import disabled
from .drivers import driver_for
from .handover import handing_over
from .params import arrays_of, attribute, getter, nested_ready, pack, spec_of

__all__ = ["Engine", "engine_for"]

#: a component's count of changes (see the module docstring)
_CHANGES = operator.attrgetter("_changes")


def engine_for(clusterer, synapse) -> "Engine | None":
    """The pair's engine, or None when it learns by the reference: a part whose own class
    declares no compiled steps (or a nested part other steps than its owner drives it with),
    kernels disabled (``NOVELTY_NO_KERNELS``)."""
    c_spec, s_spec = spec_of(clusterer), spec_of(synapse)
    if c_spec is None or s_spec is None or not nested_ready(clusterer, c_spec) or disabled():
        return None
    return Engine(clusterer, synapse, c_spec, s_spec)


class Engine:
    """The compiled loop of one (clusterer, synapse) pair, and its state (module docstring)."""

    def __init__(self, clusterer, synapse, c_spec, s_spec):
        self.clusterer, self.synapse = clusterer, synapse
        self.c_spec, self.s_spec = c_spec, s_spec
        self._read_c = getter(("weights_",) + c_spec.arrays)
        self._read_s = getter(s_spec.arrays)
        self._read_counters = getter(c_spec.counters)
        self._c_square = tuple(name in c_spec.square for name in c_spec.arrays)
        self._counter_names = c_spec.counters
        self._seen = None  # the parts' counts of changes when the engine last read them
        self._parts: tuple = ()  # those parts: the pair and its nested components
        self._compiled = None  # the driver for the arrays' types
        self._types = None  # and those types
        # the state: arrays with room for ``capacity`` units, of which the first ``n`` are units
        self.n = self.capacity = 0
        self._shown = -1  # how many units the components' views show
        self._WT = None  # the weights, transposed: (features, capacity)
        self._c_arrays: list = []
        self._s_arrays: list = []
        self._counters = None
        self._head: tuple = ()  # the driver's arguments before the scans, in one tuple
        #: the parameter records packed last (:func:`.params.pack`): ``c_record["learning_rate"]``
        self.c_record = self.s_record = None
        # a single scan's arguments, kept between calls
        self._dt1 = np.ones(1)
        self._winner1 = np.empty(1, dtype=np.int64)
        self.novelty1 = np.empty(1)
        self.distance1 = np.empty(1)
        self._one = (self._dt1,)  # the driver's arguments for one scan, around stimulus and n
        self._out1 = (self._winner1, self.novelty1, self.distance1)
        #: whether a scan is scored by its nearest unit (the clusterer declares it), and the
        #: single-scan scoring call's output: efficacy, squared distance, winner
        self.nearest_unit = declares(clusterer, "nearest-unit")
        self.scored1 = np.empty(3)
        # the owner and its parts as they were when it last confirmed that this engine serves
        # its single-scan calls (:meth:`confirm`; under the owner's lock: an engine holds no
        # lock of its own, since a fit's clone hands its engine to the detector it fitted)
        self._watched: tuple = ()
        self._watched_seen = None
        # the clusterer's counters written back into its attributes in one statement
        self._write_counters = _counter_writer(c_spec.counters)

    # ------------------------------------------------------------- the state
    def current(self) -> bool:
        """Whether the engine holds the pair's state and parameters as they are now, read again
        if a part changed since; False when the state is not in the declared layout."""
        return self.unchanged() or self._read()

    def confirm(self, owner, *others) -> None:
        """Record that ``owner`` (a filter) checked that this engine serves its single-scan calls
        as its general path would, with ``others`` (components whose change would change
        that: its unfitted parts) and this engine's parts as they are now; until one of them is
        set again, :meth:`confirmed` says so in one comparison of their counts of changes. The
        engine must be :meth:`current`."""
        self._watched = (owner, *others, *self._parts)
        self._watched_seen = tuple(map(_CHANGES, self._watched))

    def confirmed(self) -> bool:
        """Whether nothing :meth:`confirm` watches was set since (a part replaced, a parameter
        set, the views of a grown state given out: each counts a change)."""
        return tuple(map(_CHANGES, self._watched)) == self._watched_seen

    def unchanged(self) -> bool:
        """Whether no part was set since the engine read them (so it holds them as they are)."""
        return self._seen is not None and tuple(map(_CHANGES, self._parts)) == self._seen

    def _read(self) -> bool:
        self._seen = None
        c, s = self.clusterer, self.synapse
        if not nested_ready(c, self.c_spec):
            return False
        try:
            c_read, s_read = self._read_c(c), self._read_s(s)
            counters = np.array(self._read_counters(c), dtype=np.int64)
        except (AttributeError, TypeError, ValueError, OverflowError):
            return False
        if not self._check(c_read, s_read) or counters.ndim != 1:
            return False
        n = c_read[0].shape[0]
        # the engine's own copies, with room to a whole number of vectors: nobody else holds
        # them, so nobody can make them read-only or strided; the components see views of them
        capacity = whole_vectors(n)
        self._WT = _roomy_columns(c_read[0].T, n, capacity)
        self._c_arrays = [_roomy(a, sq, n, capacity) for a, sq in zip(c_read[1:], self._c_square)]
        self._s_arrays = [_roomy(a, False, n, capacity) for a in s_read]
        self.n, self.capacity = n, capacity
        self._counters = counters
        self._pack()
        self._show(n)
        return True

    def _pack(self) -> None:
        """The parameters as the driver takes them: the bytes of their records (``c_record``,
        ``s_record``: :func:`.params.pack`), which the driver views as the records again (numba
        types a plain byte array at once; a structured array by a slower path, 0.1 us a call
        each)."""
        c, s = self.clusterer, self.synapse
        self.c_record, self.s_record = pack(c), pack(s)
        types = tuple(a.dtype for a in [self._WT, *self._c_arrays, *self._s_arrays,
                                        self.c_record, self.s_record])
        if types != self._types:  # other types (another nested part's record): another driver
            self._compiled, self._types = None, types
        self._head = (self._WT, *self._c_arrays, self._counters, self.c_record.view(np.uint8),
                      *self._s_arrays, self.s_record.view(np.uint8))
        nested = tuple(getattr(c, name) for name, _ in self.c_spec.nested)
        self._parts = (c, s) + nested

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

    def _show(self, n: int) -> None:
        """Give the components views of the first ``n`` units of the engine's arrays.

        Counted as changes, which the engine then takes as seen: another engine of the same
        components (one asked for by :func:`novelty._kernels.wait`, say) reads them again
        before it would work on arrays they no longer show."""
        _put(self.clusterer, "weights_", self._WT[:, :n].T)
        for name, a, square in zip(self.c_spec.arrays, self._c_arrays, self._c_square):
            _put(self.clusterer, name, a[:n, :n] if square else a[:n])
        for name, a in zip(self.s_spec.arrays, self._s_arrays):
            _put(self.synapse, name, a[:n])
        self._shown = n
        self._seen = tuple(map(_CHANGES, self._parts))

    def _grow(self, capacity: int) -> None:
        """Move the state into arrays with room for ``capacity`` units (to a whole vector)."""
        n = self.n
        capacity = whole_vectors(capacity)
        self._WT = _roomy_columns(self._WT, n, capacity)
        self._c_arrays = [_roomy(a, sq, n, capacity) for a, sq in zip(self._c_arrays, self._c_square)]
        self._s_arrays = [_roomy(a, False, n, capacity) for a in self._s_arrays]
        self.capacity = capacity
        self._shown = -1  # the components' views are of the old arrays
        head = self._head
        k = len(self._c_arrays)
        self._head = (self._WT, *self._c_arrays, *head[1 + k:3 + k], *self._s_arrays, head[-1])

    def _finish(self, n: int) -> None:
        """After the driver: the components see the units and counters it left (as
        :meth:`learn_one` does, written out there)."""
        self.n = n
        if n != self._shown:
            self._show(n)
        if self._counter_names:
            self._write_counters(vars(self.clusterer), self._counters.tolist())

    # ------------------------------------------------------------ the driver
    def compiled(self):
        """The driver for the state's array types (a :class:`.compiling.Compiled`), or None."""
        if not self.current():
            return None
        if self._compiled is None:
            try:
                self._compiled = driver_for(self.c_spec.steps, self.s_spec.steps,
                                            type(self.clusterer), type(self.synapse), self._WT,
                                            self._c_arrays, self._s_arrays, self.c_record.dtype,
                                            self.s_record.dtype)
            except (OSError, ImportError):  # no folder to write the driver to; a steps module missing
                return None
        return self._compiled

    def learner(self, reference: Callable) -> Callable | None:
        """A function ``(clusterer, synapse, X, dt, stimulus, distances=None) -> novelty`` that
        learns compiled (or by ``reference`` block by block while the driver compiles, see
        :mod:`.handover`), or None when the pair runs the reference now."""
        if disabled():
            return None
        compiled = self.compiled()
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
        (``learn_stream``; block by block while the driver compiles)."""
        compiled = None if disabled() else self.compiled()
        if compiled is not None:
            if compiled.module is not None or compiled.get() is not None:
                return self.learn(X, dt, stimulus, distances)
            if compiled.compiling:
                return handing_over(compiled, self._learn, reference)(
                    self.clusterer, self.synapse, X, dt, stimulus, distances=distances)
        return reference(self.clusterer, self.synapse, X, dt, stimulus, distances=distances)

    def learn(self, X: np.ndarray, dt: np.ndarray, stimulus: float,
              distances: np.ndarray | None = None, winners: np.ndarray | None = None) -> np.ndarray:
        """Learn the rows of ``X`` compiled; return their novelty (the winners' efficacies).

        ``distances`` and ``winners`` (int64), if given, receive each row's squared
        distance to its winner and the winner's row (at the time of the row).
        """
        drive = self.compiled().module.drive
        X, dt = _c(X), _c(dt)
        m = X.shape[0]
        novelty = np.empty(m)
        d = np.empty(m) if distances is None else distances
        rows = np.empty(m, dtype=np.int64) if winners is None else winners
        stimulus = float(stimulus)
        n = self.n
        start = 0
        while True:
            done, n = drive(*self._head, X[start:], dt[start:], stimulus, n, rows[start:],
                            novelty[start:], d[start:], False)
            start += done
            if start >= m:
                break
            # no room for the unit the next input adds: at least double, at most one per input
            self.n = n
            self._grow(n + max(1, min(m - start, max(n, 16))))
        self._finish(n)
        return novelty

    def learn_one(self, x: np.ndarray, stimulus: float) -> bool:
        """Learn one scan compiled, the driver checking it first; its novelty (the winner's
        efficacy) and squared distance to its winner are then ``novelty1[0]`` and
        ``distance1[0]``. False, with nothing learned, when the driver is not loaded yet or the
        check fails: the caller then takes its general path, which checks the scan and says
        what is wrong with it.

        The caller holds the owner's lock, has made sure the engine is :meth:`current`, and
        passes a C-contiguous, writable 1-D float64 array. The driver's check: as many features
        as the units have, and a sum of squares within the norm bound with a margin
        (``novelty._validation.scans.CLEARED``, far wider than rounding), so that NaN, infinity
        and too large values all fail it. (False too while ``NOVELTY_NO_KERNELS`` asks for the
        reference.)
        """
        compiled = self._compiled
        if compiled is None or compiled.module is None or disabled():
            return False
        drive = compiled.module.drive
        X = x[None, :]
        while True:
            done, n = drive(*self._head, X, *self._one, stimulus, self.n, *self._out1, True)
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

    def score_one(self, kernels, x: np.ndarray) -> bool:
        """Score one scan compiled (``kernels``: the compiled :mod:`._nearest`), checked first as
        :meth:`learn_one` checks it: its nearest unit's efficacy, squared distance and row are
        then ``scored1``. False, with nothing written, when the check fails. The caller holds
        the owner's lock, has made sure the engine is :meth:`unchanged` and its clusterer a
        ``"nearest-unit"`` one, and passes a C-contiguous, writable 1-D float64 array."""
        return kernels.nearest_one(self._WT, self._s_arrays[0], self.n, x, self.scored1) == 0

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


def _roomy(a: np.ndarray, square: bool, n: int, capacity: int) -> np.ndarray:
    """The first ``n`` units of ``a`` in a new array with room for ``capacity``, zero."""
    b = np.zeros((capacity, capacity) if square else (capacity,) + a.shape[1:], dtype=a.dtype)
    if square:
        b[:n, :n] = a[:n, :n]
    else:
        b[:n] = a[:n]
    return b


@functools.lru_cache(maxsize=64)  # compiling one costs 60 us, a tenth of a short stream call
def _counter_writer(names: tuple[str, ...]) -> Callable:
    """``write(d, values)``: ``d[name] = value`` for the counters' names and values, as one
    unpacking assignment compiled for these names (as :func:`collections.namedtuple` compiles
    its class): 0.1 us a single scan for the SOM's two counters, where ``d.update(zip(names,
    values))`` took 0.35 us. The names are quoted as string literals (``repr``), so any name
    is only ever a key."""
    if not names:
        return lambda d, values: None
    targets = "".join(f"d[{name!r}], " for name in names)
    namespace: dict = {}
    exec(f"def write(d, values):\n    {targets}= values\n", namespace)
    return namespace["write"]


#: the units of a vector in the distance loops (``novelty._kernels._distances.VECTOR``, which
#: imports numba, as this module must not: a test keeps the two equal)
VECTOR = 8


def whole_vectors(capacity: int) -> int:
    """``capacity`` rounded up to whole vectors: the distance loops then run over whole
    vectors of columns, the room past the units zero (finite: no slow path on garbage), with
    no scalar remainder (100 units: 12 vectors and 4 units one at a time took a fifth longer
    than 13 vectors)."""
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
