"""Damaging a fitted filter's state on purpose, as nothing in the library may.

A fitted part is read-only (:meth:`novelty._component.Component.__setattr__`): its attributes may
be set, and its learned arrays written, only inside its engine's writes. The engine still checks
what it reads before every call (:mod:`novelty._kernels.state`, ``Engine.check_values``), for a
state damaged all the same: an array made writable again on purpose, a plugin's step writing
where it should not, memory changed under a process. These tests build such states by writing
as the engine does, through :func:`novelty._component.engine_writes`.
"""

import contextlib

from novelty._component import engine_writes
from novelty._kernels.state import parts_of


@contextlib.contextmanager
def damaging(det):
    """The block in which a test sets attributes on ``det``'s fitted parts (a filter's, or a
    tuple of components) and writes into their learned arrays; the engine notices what was set
    (its counts of changes) as after its own writes, and checks the values before its next call."""
    parts = det if isinstance(det, tuple) else parts_of(det.clusterer_, det.synapse_)
    with engine_writes(parts):
        yield
