"""The Growing Neural Gas in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

``match`` and ``adapt`` do what ``GrowingNeuralGas.match`` and ``.adapt`` do
(steps 2-9), on arrays with room for more units: ``state`` is ``(errors_,
edge_ages_, unit_ids_)``, ``counters`` ``(n_inputs_, next_unit_id_)``, ``p``
the record of ``GrowingNeuralGas._kernel.params`` (``p.epsilon_b``, ...).
"""

from __future__ import annotations

from .._jit import compiled, step
from . import _graph_steps as graph
from ._graph import NO_EDGE
from .base import move_towards
from .gng import GrowingNeuralGas

N_INPUTS, NEXT_ID = (GrowingNeuralGas._kernel.counters.index(name)
                     for name in ("n_inputs_", "next_unit_id_"))

_move = compiled(move_towards)


@step
def match(d, n, state, counters, p, nb):
    """Step 2: the nearest unit s1, the second-nearest s2, and s1's neighbours into ``nb``."""
    s1 = graph.nearest(d, n)
    return s1, graph.runner_up(d, n, s1), graph.neighbours(state[1], n, s1, nb)


@step
def room(d, winner, n, state, counters, p):
    """One unit when this input is an insertion step (step 8) below ``max_units``."""
    due = (counters[N_INPUTS] + 1) % p.insertion_interval == 0
    return 1 if due and n < p.max_units else 0


@step
def adapt(WT, x, d, s1, s2, nb, k, n, state, counters, p, gone):
    """Steps 3-9; returns (units, removed, added, new unit wins)."""
    E, A, ids = state
    graph.age_edges(A, n, s1)                                           # step 3
    E[s1] += d[s1]  # step 4: ((x - w)**2).sum() is d[s1], the same numbers in the same order
    for f in range(WT.shape[0]):                                        # step 5
        WT[f, s1] = _move(WT[f, s1], x[f], p.epsilon_b)
    for m in range(k):
        j = nb[m]
        for f in range(WT.shape[0]):
            WT[f, j] = _move(WT[f, j], x[f], p.epsilon_n)
    graph.connect(A, s1, s2, 0)                                         # step 6
    removed = graph.prune(A, n, s1, p.max_age, gone)                    # step 7
    if removed:
        n = graph.delete_units(n, gone, WT, A, ids, E)
    counters[N_INPUTS] += 1
    added = 0
    if counters[N_INPUTS] % p.insertion_interval == 0 and n < p.max_units:  # step 8
        q = 0
        for j in range(1, n):
            if E[j] > E[q]:
                q = j
        f = -1
        for j in range(n):
            if A[q, j] >= 0 and (f < 0 or E[j] > E[f]):
                f = j
        if f < 0:  # cannot happen after the first input: every unit has an edge
            raise RuntimeError("GrowingNeuralGas: the unit of largest error has no neighbour.")
        E[q] *= p.insertion_error_decay
        E[f] *= p.insertion_error_decay
        r = n
        for c in range(WT.shape[0]):
            WT[c, r] = 0.5 * (WT[c, q] + WT[c, f])
        E[r] = E[q]
        ids[r] = counters[NEXT_ID]
        counters[NEXT_ID] += 1
        graph.new_unit(A, n)
        n += 1
        graph.connect(A, q, f, NO_EDGE)
        graph.connect(A, q, r, 0)
        graph.connect(A, r, f, 0)
        added = 1
    for j in range(n):                                                  # step 9
        E[j] *= 1.0 - p.error_decay
    return n, removed, added, False
