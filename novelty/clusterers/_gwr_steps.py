"""The Grow-When-Required network in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

``match`` and ``adapt`` do what ``GrowWhenRequired.match`` and ``.adapt`` do
(steps 3-11), on arrays with room for more units: ``state`` is
``(firing_.efficacy_, edge_ages_, unit_ids_)``, ``counters``
``(next_unit_id_,)``, ``p`` the record of ``GrowWhenRequired._kernel.params``:
``p.max_units`` (``p.has_max_units`` false for None), ``p.activity_threshold_``
(fitted), and ``p.firing_``, the firing counters' own record (a Stanley bank:
its equation is :mod:`novelty.habituation._stanley_steps`, its schedule the one
every synapse follows, :mod:`novelty.habituation._schedule`, with the bank's own
schedule parameters, ``p.firing_.tau_winner`` and the rest).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import compiled, step
from ..habituation.steps import fire, stimulate
from ..habituation.steps import stanley_steps as firing
from . import _graph_steps as graph
from ._graph import NO_EDGE
from .base import move_towards
from .gwr import GrowWhenRequired

NEXT_ID = GrowWhenRequired._kernel.counters.index("next_unit_id_")

_move = compiled(move_towards)


@step
def match(d, n, state, counters, p, nb):
    """Steps 3-4: the winner s, the runner-up t, and the units that learn with s (its
    neighbours and t, ascending) into ``nb``."""
    s = graph.nearest(d, n)
    t = graph.runner_up(d, n, s)
    A = state[1]
    k = 0
    for j in range(n):
        if A[s, j] >= 0 or j == t:
            nb[k] = j
            k += 1
    return s, t, k


@step
def room(d, s, n, state, counters, p):
    """One unit when step 7 adds one for this input. ``((x - w_s)**2).sum()`` is ``d[s]``.
    sqrt is correctly rounded everywhere; exp is the C library's here and numpy's in the
    reference, which may differ in the last bit (it matters only at a_T exactly)."""
    activity = math.exp(-math.sqrt(d[s]))
    h = state[0]
    grow = (activity < p.activity_threshold_
            and (h[s] < p.habituation_threshold or not p.firing_condition)
            and (not p.has_max_units or n < p.max_units))
    return 1 if grow else 0


@step
def adapt(WT, x, d, s, t, nb, k, n, state, counters, p, gone):
    """Steps 5-11; returns (units, removed, added, new unit wins)."""
    h, A, ids = state
    ph = p.firing_
    grow = room(d, s, n, state, counters, p) == 1  # step 6, before step 5 changes nothing it reads
    graph.connect(A, s, t, 0)                                           # step 5
    r = n
    if grow:                                                            # step 7
        for f in range(WT.shape[0]):
            WT[f, r] = 0.5 * (WT[f, s] + x[f])
        firing.fresh((h,), r, ph)
        ids[r] = counters[NEXT_ID]
        counters[NEXT_ID] += 1
        graph.new_unit(A, n)
        n += 1
        graph.connect(A, r, s, 0)
        graph.connect(A, r, t, 0)
        graph.connect(A, s, t, NO_EDGE)
    else:                                                               # step 8
        for f in range(WT.shape[0]):
            WT[f, s] = _move(WT[f, s], x[f], p.epsilon_b * h[s])
        for j in range(n):
            if A[s, j] >= 0:
                for f in range(WT.shape[0]):
                    WT[f, j] = _move(WT[f, j], x[f], p.epsilon_n * h[j])
    graph.age_edges(A, n, s)                                            # step 9
    around = np.empty(n, dtype=np.int64)                                # step 10
    rows = np.empty(n, dtype=np.int64)
    stimulate(firing.advance, (h,), n, s, around, graph.neighbours(A, n, s, around), 1.0, 1.0,
              ph, gone, rows)
    new_wins = grow and p.new_unit_wins
    if new_wins:  # the new unit fires for the input too
        fire(firing.advance, (h,), r, 1.0, 1.0, ph, rows)
    removed = graph.prune(A, n, s, p.max_age, gone)               # step 11
    if removed:
        n = graph.delete_units(n, gone, WT, A, ids, h)
    return n, removed, 1 if grow else 0, new_wins
