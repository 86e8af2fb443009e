"""Which engine a fitted filter gets, and why: decided here, and nowhere else.

A filter holds one engine (:mod:`.interface`) for its fitted parts and asks
for it on every call (:func:`engine_for`). While the engine holds the parts as
they are (:meth:`~.interface.Engine.holds`: nothing set on them since it read
them, ``NOVELTY_NO_KERNELS`` as it was, no kernel it waited for ready since),
it is the one; otherwise the state is checked (:func:`.state.check_state`,
which refuses what no engine may read) and :func:`choose` makes another. A
deep copy of a filter holds, instead of an engine, a
:class:`~.interface.CheckedCopy`: its parts are a copy of a checked state, so
while nothing was set on them since, its first engine is made after the layout
alone is checked (:func:`.state.check_layout`: a copy made while a thread
learned may be torn).

The reasons to use the reference (:class:`~.reference.ReferenceEngine`), all here:

- learning: a part whose own class declares no compiled steps (a plugin, or a
  subclass, which may change the arithmetic), a nested part that declares
  other steps than its owner drives it with, ``NOVELTY_NO_KERNELS`` set to a
  non-empty value other than ``0``, a state the declared steps cannot take
  (an array the spec names missing, the synapse's first array not its
  efficacy), numba missing or failing to compile (one ``RuntimeWarning``);
  and, while the pair's driver compiles in the background, the reference
  learns, block by block, until it hands over (:mod:`.handover`);
- scoring: a clusterer that does not declare ``"nearest-unit"``, the
  variable, numba; while the scoring kernels compile, the reference scores.

When neither learning nor scoring compiles, the engine is a
:class:`~.reference.ReferenceEngine`; otherwise a
:class:`~.engine.CompiledEngine` told which halves compile.
"""

from __future__ import annotations

import numpy as np

from .._component import declares
from .compiling import Compiled, disabled
from .engine import CompiledEngine, driver_of
from .interface import CheckedCopy, Engine
from .params import attribute, nested_ready, pack, spec_of
from .reference import ReferenceEngine
from .state import check_layout, check_state

__all__ = ["engine_for", "choose", "why_not_learning", "why_not_scoring", "NEAREST"]

#: the nearest-unit kernels of batch and single-scan scoring (:mod:`._nearest`)
NEAREST = Compiled("novelty._kernels._nearest")


def engine_for(held, detector) -> Engine:
    """The engine of a fitted filter's parts as they are now: ``held``, the one the filter
    holds, while it holds them, else a new one (module docstring). ``held`` is the filter's
    engine, a deep copy's :class:`~.interface.CheckedCopy` or None; the filter keeps what this
    returns, its one writer (``HabituatingFilter._current_engine``)."""
    if isinstance(held, Engine):
        if held.clusterer is detector.clusterer_ and held.synapse is detector.synapse_ and held.holds():
            return held
        check_state(detector)
    elif isinstance(held, CheckedCopy) and held.covers(detector):
        check_layout(detector)  # a copy of a checked state: torn by a thread, though?
    else:
        check_state(detector)
    return choose(detector.clusterer_, detector.synapse_)


def why_not_learning(clusterer, synapse) -> str | None:
    """Why the pair cannot learn compiled, whatever the compiler does; None when it can."""
    for part in (clusterer, synapse):
        if spec_of(part) is None:
            return f"{type(part).__name__} declares no compiled steps"
    if not nested_ready(clusterer, spec_of(clusterer)):
        return f"{type(clusterer).__name__}'s parts declare other steps"
    if disabled():
        return "NOVELTY_NO_KERNELS"
    if hasattr(clusterer, "weights_") and not _in_layout(clusterer, synapse):
        return "state not in the declared layout"
    return None


def why_not_scoring(clusterer) -> str | None:
    """Why the clusterer's scans cannot be scored compiled; None when they can."""
    if not declares(clusterer, "nearest-unit"):
        return f"{type(clusterer).__name__} does not declare nearest-unit"
    if disabled():
        return "NOVELTY_NO_KERNELS"
    return None


def choose(clusterer, synapse) -> Engine:
    """A new engine for the fitted parts (their state checked): the reasons of the module
    docstring, in one place."""
    learning, scoring = why_not_learning(clusterer, synapse), why_not_scoring(clusterer)
    driver = compiling = module = records = None
    pending = []
    if learning is None:
        try:
            records = (pack(clusterer), pack(synapse))  # packed once: the driver's types, its bytes
            found = driver_of(clusterer, synapse, records)
        except (OSError, ImportError) as exc:  # no folder to write the driver to; a steps module missing
            learning = f"kernels unavailable: {exc}"
        else:
            learning, driver, compiling = _readiness(found)
            pending += [compiling] if compiling is not None else []
    if scoring is None:
        scoring, ready, waiting = _readiness(NEAREST)
        module = None if ready is None else ready.module
        pending += [waiting] if waiting is not None else []
    if driver is None and compiling is None and module is None:
        return ReferenceEngine(clusterer, synapse, f"reference ({learning})", tuple(pending))
    engine = CompiledEngine(clusterer, synapse, driver, compiling, module, tuple(pending), records)
    if learning is not None:
        engine.why = f"reference ({learning})"
    return engine


def _readiness(compiled: Compiled) -> tuple:
    """``(why not, ready, compiling)`` of a module of kernels: ``(None, compiled, None)`` when
    loaded, ``(None, None, compiled)`` while it compiles in the background (asked for now if
    it was not), ``("kernels unavailable: ...", None, None)`` when it failed (warned once)."""
    if compiled.module is not None or compiled.get() is not None:
        return None, compiled, None
    if compiled.compiling:
        return None, None, compiled
    if compiled.error is not None or compiled.failed:
        return f"kernels unavailable: {compiled.error}", None, None
    return "NOVELTY_NO_KERNELS", None, None  # disabled when it was first asked for


def _in_layout(clusterer, synapse) -> bool:
    """Whether the state is what the declared steps take: every array the specs name exists
    (a numpy array), and the synapse's first is its efficacy (the drivers read it as such)."""
    c_spec, s_spec = spec_of(clusterer), spec_of(synapse)
    if not s_spec.arrays or s_spec.arrays[0] != "efficacy_":
        return False
    for part, spec in ((clusterer, c_spec), (synapse, s_spec)):
        for name in spec.arrays:
            try:
                value = attribute(part, name)
            except AttributeError:
                return False
            if type(value) is not np.ndarray or value.dtype == object:
                return False
    return True
