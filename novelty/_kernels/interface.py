"""The engine interface: what a habituating filter asks of the arithmetic of its fitted pair.

A filter (:class:`novelty.filter.HabituatingFilter`) holds one engine for its
fitted clusterer and synapse bank and never asks which kind it is. Two kinds
implement the same methods:

- :class:`~novelty._kernels.reference.ReferenceEngine`, numpy: the readable loop
  (:func:`~novelty._kernels.reference.learn_stream`), the specification;
- :class:`~novelty._kernels.engine.CompiledEngine`, numba: the same arithmetic in
  one generated loop per pair, equal to the reference bit for bit.

Which one a filter gets, and why, is decided in one place,
:func:`novelty._kernels.choice.engine_for`; what an engine reads is checked in
one place before it reads it, :func:`novelty._kernels.state.check_state`.

The methods (``X`` a C-contiguous float64 batch the filter checked, ``x`` one scan):

- ``learn(X, dt, stimulus, distances=None) -> novelty``: the rows of ``X`` in
  order, learning, the network growing and shrinking as it needs; each row's
  novelty is its winner's efficacy before the row is learned, ``distances``
  receives each row's squared distance to its winner;
- ``learn_one(x, stimulus) -> bool``: one scan learned, its novelty and squared
  distance then in ``novelty1[0]`` and ``distance1[0]``; False, with nothing
  learned, for a scan outside the checks (as many features as the units, a
  sum of squares within the norm bound): the filter's general path then says
  what is wrong with it;
- ``score(X) -> (rows, distances, efficacy)``: without learning, each scan's
  nearest unit (row), its squared distance and its efficacy;
- ``score_one(x) -> bool``: ``score`` of one scan, into ``scored1``
  (efficacy, squared distance, row); False as ``learn_one``;
- ``nearest(X) -> (rows, distances)``: the nearest units alone;
- ``learn_calibrating(X, dt, stimulus, calibration, scale, distances=None) ->
  (efficacy, scales, scale)``: ``learn`` while the match scale is calibrated, the new
  scales given to the clusterer (:meth:`Engine.calibrate`), one loop for every engine
  (:meth:`~novelty._kernels.reference.ReferenceEngine.learn_calibrating`).

**Freshness.** An engine reads the parts when it is made. The parts are
read-only outside its writes (:func:`novelty._component.engine_writes`), but
the objects it watches besides them (the filter that owns it, the templates
of its parts) are set at will, as scikit-learn's contract allows; setting an
attribute of any of them counts a change
(:meth:`novelty._component.Component.__setattr__`), so
:meth:`Engine.holds` compares one count per part with those it saw (and
:meth:`Engine.fresh` one per object it watches: the owner's too). Its own
writes (the counters, a grown state's views) it takes as seen. On the parts,
a count moves only by the engine's writes, the checks it calls and a write
made past the lock on purpose (``vars``, ``engine_writes``); the compiled
engine still notices the last, one comparison a call, because it reads its own
copies of the arrays (a replaced array it did not notice would otherwise be
scored against, or read past, by the scoring kernels).

Two predicates, not one, because they answer two questions. ``holds``: may
this engine go on reading the parts (every call, :func:`~.choice.engine_for`);
``fresh``: may a single scan also skip the owner's checks (its parameters,
timestamps, calibration), which only :mod:`novelty._filter.single_scan` asks.
Folded into one comparison of the watched objects, every write to the owner
(``last_time_``, at every timestamped call) would make ``engine_for`` check
the state and build another engine, several times the cost of a whole
timestamped call of 10 scans (docs/guide/performance.md); folded the other
way (``holds`` and a separate comparison of the owner's counts), a single
scan would make two comparisons where it makes one.
"""

from __future__ import annotations

import copy
import operator

import numpy as np

from .._component import StateError, engine_writes, held_by_engine
from .compiling import disabled
from .params import spec_of
from .._validation.scans import cleared
from .state import check_efficacies, check_finite, parts_of

__all__ = ["Engine", "CheckedCopy", "ONE"]

#: an object's count of changes (:meth:`novelty._component.Component.__setattr__`)
_CHANGES = operator.attrgetter("_changes")

#: the elapsed time of a scan learned alone, without a timestamp
ONE = np.ones(1)
ONE.setflags(write=False)


class Engine:
    """The arithmetic of one fitted (clusterer, synapse) pair (module docstring).

    ``why`` says which engine it is, as the filter's ``compiled_`` reports it:
    ``"compiled"`` or ``"reference (<why>)"``.
    """

    why = "reference"
    #: the kernels (:class:`~novelty._kernels.compiling.Compiled`) still compiling in the
    #: background when the engine was chosen: once one is ready (or failed), another is chosen
    pending: tuple = ()

    def __init__(self, clusterer, synapse):
        self.clusterer, self.synapse = clusterer, synapse
        self.parts = parts_of(clusterer, synapse)
        for part in self.parts:  # the engine is the one writer of what they learned
            held_by_engine(part)
        #: the features of a scan: the weights' columns (checked against the filter's scans)
        self.width = clusterer.weights_.shape[1]
        self.novelty1, self.distance1 = np.empty(1), np.empty(1)
        self.scored1 = np.empty(3)
        self._watched = self.parts
        self._seen = None  # nothing confirmed by an owner yet (watch): never fresh
        self._parts_seen = ()
        self._values_seen = None  # the counts check_values listed its arrays at (none yet)
        self._disabled = disabled()

    # ------------------------------------------------------------ freshness
    def holds(self) -> bool:
        """Whether the engine holds the parts as they are: none was set since it read them (or
        since its own writes), and ``NOVELTY_NO_KERNELS`` says what it said when the engine was
        chosen, and no kernel it waited for is ready since. Every call asks it first; when it fails, the filter has another engine chosen
        (:func:`novelty._kernels.choice.engine_for`)."""
        return (tuple(map(_CHANGES, self.parts)) == self._parts_seen and disabled() == self._disabled
                and not (self.pending and _settled(self.pending)))

    def fresh(self) -> bool:
        """:meth:`holds`, and none of the objects given to :meth:`watch` (the owner, its
        unfitted parts) was set since: one comparison, what a single scan's call asks."""
        return (tuple(map(_CHANGES, self._watched)) == self._seen and disabled() == self._disabled
                and not (self.pending and _settled(self.pending)))

    def watch(self, *others) -> None:
        """Watch ``others`` besides the parts (:meth:`fresh`), all taken as seen now: the owner
        calls it once its checks passed."""
        self._watched = others + self.parts
        self._seen = None
        self.seen()

    def seen(self) -> None:
        """Take the parts as they are now as seen (after the engine's own writes); and every
        watched object, once something is watched."""
        self._parts_seen = tuple(map(_CHANGES, self.parts))
        if self._watched is not self.parts:
            self._seen = tuple(map(_CHANGES, self._watched))

    def calibrate(self, scale) -> None:
        """``Clusterer.calibrate(scale)`` of the engine's clusterer, which the filter calls
        after each new match scale (:mod:`novelty._filter.calibration`: one scan at a time,
        up to 200 of them for GWR's ``"auto"`` radius).

        Taken without another engine when all it set is what the clusterer's steps declare as
        fitted parameters (``KernelSpec.fitted``: GWR's ``activity_threshold_``), each a finite
        number: then :meth:`take_parameters`, and the parts are seen. Anything else it set (an
        array, a counter, another attribute) leaves the parts unseen: the next call has another
        engine chosen after the full check (:func:`~.state.check_state`), as after any other
        change. Choosing one after every calibrating scan cost far more than learning the scan.
        """
        clusterer = self.clusterer
        before = dict(vars(clusterer))
        others = [part for part in self.parts if part is not clusterer]  # the synapse, nested parts
        counts = tuple(map(_CHANGES, others))
        held = self.holds()
        with engine_writes(self.parts):
            clusterer.calibrate(scale)
        if not held or tuple(map(_CHANGES, others)) != counts:
            return
        after = vars(clusterer)
        changed = {name for name in before.keys() | after.keys()
                   if name not in _BOOKKEEPING and before.get(name, _GONE) is not after.get(name, _GONE)}
        spec = spec_of(clusterer)
        fitted = {name for name, _ in spec.fitted} if spec is not None else set()
        if changed <= fitted and all(_finite_number(after.get(name)) for name in changed) \
                and self.take_parameters():
            # the parts only: the owner's own change (its match scale) stays for fresh() to see
            self._parts_seen = tuple(map(_CHANGES, self.parts))

    def take_parameters(self) -> bool:
        """Read the parts' parameters again (after :meth:`calibrate`); False if they cannot be
        taken in place. The reference reads them from the parts at every call."""
        return True

    # ---------------------------------------------------------- the checks
    def check_scans(self, X: np.ndarray) -> None:
        """Refuse scans of another width than the units' (``n_features_in_`` set since)."""
        if X.shape[1] != self.width:
            raise StateError(f"The scans have {X.shape[1]} features but the clusterer's weights have "
                             f"{self.width}: n_features_in_ no longer matches the learned state. Refit.")

    def state_arrays(self) -> list:
        """``(name, array)`` of the float state the engine reads, for :func:`check_finite`."""
        return [(f"{type(part).__name__}.{name}", value) for part in self.parts
                for name, value in vars(part).items()
                if name.endswith("_") and type(value) is np.ndarray and value.dtype.kind == "f"]

    def check_values(self) -> None:
        """:func:`check_finite` of the state, every synapse's efficacies within the scans' norm
        bound (:func:`~.state.check_efficacies`) and the units within the norm bound
        (``Clusterer._check_norm``): before every call, for values written in place (the
        compiled single-scan calls check them in the driver, and leave a state that fails to
        the general path, which calls this).

        One sum of squares an array clears it (as the scans are cleared,
        ``novelty._validation.scans``): a sum within ``CLEARED`` has every value finite and
        every row's norm within the bound (a sum of non-negative squares bounds each of them,
        and the margin covers rounding); NaN, infinity and too large values all fail the
        comparison, and then the checks that name what is wrong run. The arrays are listed
        again only when a part was set since (a count per part): listing them at every call
        was a large share of a call that scores one scan."""
        counts = tuple(map(_CHANGES, self.parts))
        if counts != self._values_seen:
            self._values = self.value_arrays()
            self._values_seen = counts
        if all(map(cleared, self._values)):
            return
        check_finite(self.state_arrays())
        check_efficacies(self.parts)
        self.clusterer._check_norm()

    def value_arrays(self) -> list:
        """The arrays :meth:`check_values` sums (:meth:`state_arrays`' arrays, each flat where
        its memory is contiguous)."""
        return [flat(a) for _, a in self.state_arrays()]

    def __reduce__(self):
        # an engine is scratch: a copy or a pickle of its filter makes its own
        return _dropped, ()

    def __deepcopy__(self, memo):
        """What a deep copy of the filter holds instead: its own engine is made at its first
        call, but from a state that is a copy of one that passed :func:`~.state.check_state`
        (:class:`CheckedCopy`), when this engine still holds its parts (else nothing). A
        pickle holds nothing (:meth:`__reduce__`): a file is checked when it is read."""
        if not self.holds():
            return None
        return CheckedCopy(copy.deepcopy(self.clusterer, memo), copy.deepcopy(self.synapse, memo),
                           self.width)


class CheckedCopy:
    """In a deep copy of a filter, in place of the engine: the copied parts, a copy of a state
    that passed :func:`~.state.check_state` (the engine held them when they were copied),
    with their counts of changes at that time. While nothing was set on them since
    (:meth:`covers`), the copy's first call takes its engine after the layout alone
    (:func:`~.state.check_layout`: types and shapes, which a copy made while a thread
    learned may tear) instead of the whole check (a large share of a call that learns a thousand
    scans), as the original goes on with its engine: values written into an
    array in place are checked before every call by both (:meth:`Engine.check_values`)."""

    def __init__(self, clusterer, synapse, width: int):
        self.clusterer, self.synapse, self.width = clusterer, synapse, width
        self.counts = tuple(map(_CHANGES, parts_of(clusterer, synapse)))

    def covers(self, detector) -> bool:
        """Whether ``detector``'s fitted parts are the copied ones, nothing set on them since,
        and its scans as wide as theirs."""
        return (detector.clusterer_ is self.clusterer and detector.synapse_ is self.synapse
                and vars(detector).get("n_features_in_") == self.width
                and tuple(map(_CHANGES, parts_of(self.clusterer, self.synapse))) == self.counts)

    def __reduce__(self):
        return _dropped, ()


#: an attribute that is not there (``None`` may be one's value)
_GONE = object()
#: a component's own bookkeeping, not what it learned: its count of changes, the marks of the engine
#: that holds and writes it (:func:`novelty._component.held_by_engine`, ``engine_writes``)
_BOOKKEEPING = ("_changes", "_held", "_writing", "_locked")


def _finite_number(value) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_)) \
        and bool(np.isfinite(value))


def flat(a: np.ndarray) -> np.ndarray:
    """``a`` as one row of its values where its memory is contiguous (a view), else as it is."""
    return a.reshape(-1) if a.flags.c_contiguous else a


def _settled(pending) -> bool:
    return any(c.module is not None or c.error is not None for c in pending)


def _dropped():
    return None
