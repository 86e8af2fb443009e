"""The SOM in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

:func:`~novelty.clusterers.som.scheduled` and
:func:`~novelty.clusterers.base.move_towards` compiled as they are; ``match``
and ``adapt`` do what ``SOM.match`` and ``SOM.adapt`` do. ``p`` is the
record of ``SOM._kernel.params`` (``p.learning_rate``, ``p.decay`` one of
the codes below, ``p.has_neighbour_learning_rate`` false for None);
``counters`` holds ``n_updates_`` and the grid radius in use.
"""

from __future__ import annotations

import math

from .._jit import compiled, step
from .._kernels.params import option_code
from ._graph_steps import nearest
from .base import move_towards
from .som import SOM, scheduled

CONSTANT = option_code(SOM, "decay", "constant")
T, TABLE_RADIUS = (SOM._kernel.counters.index(name) for name in ("n_updates_", "_table_radius"))

_scheduled = compiled(scheduled)
_move = compiled(move_towards)


@step
def match(d, n, state, counters, p, nb):
    """The winner and its square grid neighbourhood, ascending, into ``nb`` (SOM.match)."""
    winner = nearest(d, n)
    n_columns = p.n_columns
    n_rows = p.n_rows
    radius = counters[TABLE_RADIUS]
    wr = winner // n_columns
    wc = winner - wr * n_columns
    k = 0
    for r in range(max(0, wr - radius), min(n_rows - 1, wr + radius) + 1):
        for c in range(max(0, wc - radius), min(n_columns - 1, wc + radius) + 1):
            j = r * n_columns + c
            if j != winner:
                nb[k] = j
                k += 1
    return winner, -1, k


@step
def room(d, winner, n, state, counters, p):
    """A map never grows."""
    return 0


@step
def adapt(WT, x, d, winner, runner_up, nb, k, n, state, counters, p, gone):
    """SOM.adapt: the winner and ``nb[:k]`` move towards ``x``; the schedules advance."""
    t = counters[T]
    lr = _scheduled(p.decay, p.learning_rate, p.learning_rate_final, t, p.decay_steps)
    lr_n = p.neighbour_learning_rate if p.has_neighbour_learning_rate else lr
    for m in range(k):
        j = nb[m]
        for f in range(WT.shape[0]):
            WT[f, j] = _move(WT[f, j], x[f], lr_n)
    for f in range(WT.shape[0]):
        WT[f, winner] = _move(WT[f, winner], x[f], lr)
    counters[T] = t + 1
    if p.decay != CONSTANT:
        r = _scheduled(p.decay, p.radius, p.radius_final, t + 1, p.decay_steps)
        counters[TABLE_RADIUS] = int(math.floor(r + 0.5))
    return n, 0, 0, False
