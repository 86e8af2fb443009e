"""Online k-means in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

``state`` is ``(counts_, unit_ids_)``, ``counters`` ``(next_unit_id_,)``; ``p``
the record of ``OnlineKMeans._kernel.params`` (``p.learning_rate_is_count`` for
``learning_rate="count"``, ``p.init`` a code, ``p.placement_radius_`` fitted).
"""

from __future__ import annotations

from .._jit import compiled, step
from .._kernels.params import option_code
from ._graph_steps import nearest
from .base import move_towards
from .kmeans import OnlineKMeans

FIRST = option_code(OnlineKMeans, "init", "first")
NEXT_ID = OnlineKMeans._kernel.counters.index("next_unit_id_")

_move = compiled(move_towards)


@step
def match(d, n, state, counters, p, nb):
    """The nearest unit; nothing learns with it (OnlineKMeans.match)."""
    return nearest(d, n), -1, 0


@step
def room(d, winner, n, state, counters, p):
    """One unit while ``init="first"`` places inputs farther than the placement radius."""
    r = p.placement_radius_
    return 1 if p.init == FIRST and n < p.n_clusters and d[winner] > 0.0 and d[winner] > r * r else 0


@step
def adapt(WT, x, d, winner, runner_up, nb, k, n, state, counters, p, gone):
    """OnlineKMeans.adapt: an input placed as a unit of its own (``init="first"``), or the
    winner moves to the running mean of its inputs (or by a constant rate)."""
    counts, ids = state
    if room(d, winner, n, state, counters, p):
        for f in range(WT.shape[0]):
            WT[f, n] = x[f]
        counts[n] = 1
        ids[n] = counters[NEXT_ID]
        counters[NEXT_ID] += 1
        return n + 1, 0, 1, True
    counts[winner] += 1
    rate = 1.0 / counts[winner] if p.learning_rate_is_count else p.learning_rate
    for f in range(WT.shape[0]):
        WT[f, winner] = _move(WT[f, winner], x[f], rate)
    return n, 0, 0, False
