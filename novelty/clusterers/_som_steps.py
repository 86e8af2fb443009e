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
from .._kernels._lanes import move_four
from .._kernels.params import option_code
from ._graph_steps import nearest
from .base import move_towards
from .som import SOM, scheduled

CONSTANT = option_code(SOM, "decay", "constant")
T, TABLE_RADIUS = (SOM._kernel.counters.index(name) for name in ("n_updates_", "_table_radius"))

_scheduled = compiled(scheduled)
_move = compiled(move_towards)


@step
def square(winner, p, radius):
    """The grid rows and columns of the square of ``radius`` around ``winner``, clipped to the
    map: ``(first row, last row, first column, last column)``."""
    wr = winner // p.n_columns
    wc = winner - wr * p.n_columns
    return (max(0, wr - radius), min(p.n_rows - 1, wr + radius),
            max(0, wc - radius), min(p.n_columns - 1, wc + radius))


@step
def match(d, n, state, counters, p, nb):
    """The winner and its square grid neighbourhood, ascending, into ``nb`` (SOM.match)."""
    winner = nearest(d, n)
    r_lo, r_hi, c_lo, c_hi = square(winner, p, counters[TABLE_RADIUS])
    k = 0
    for r in range(r_lo, r_hi + 1):
        for j in range(r * p.n_columns + c_lo, r * p.n_columns + c_hi + 1):
            nb[k] = j
            k += j != winner  # the winner's place is taken by the next unit: no branch
    return winner, -1, k


@step
def room(d, winner, n, state, counters, p):
    """A map never grows."""
    return 0


@step
def adapt(WT, x, d, winner, runner_up, nb, k, n, state, counters, p, gone):
    """SOM.adapt: the winner and its square (``nb[:k]``) move towards ``x``; the schedules
    advance. Each grid row of the square is a run of neighbouring columns of ``WT``: moved four
    at a time (``move_four``) where the matrix has four columns from the run's start."""
    t = counters[T]
    lr = _scheduled(p.decay, p.learning_rate, p.learning_rate_final, t, p.decay_steps)
    lr_n = p.neighbour_learning_rate if p.has_neighbour_learning_rate else lr
    r_lo, r_hi, c_lo, c_hi = square(winner, p, counters[TABLE_RADIUS])
    for r in range(r_lo, r_hi + 1):
        for c in range(c_lo, c_hi + 1, 4):
            j0 = r * p.n_columns + c
            count = min(4, c_hi + 1 - c)
            if j0 + 4 <= WT.shape[1]:
                r0 = lr if j0 == winner else lr_n
                r1 = lr if j0 + 1 == winner else lr_n
                r2 = lr if j0 + 2 == winner else lr_n
                r3 = lr if j0 + 3 == winner else lr_n
                for f in range(WT.shape[0]):
                    move_four(WT, f, j0, x[f], r0, r1, r2, r3, count)
            else:
                for j in range(j0, j0 + count):
                    rate = lr if j == winner else lr_n
                    for f in range(WT.shape[0]):
                        WT[f, j] = _move(WT[f, j], x[f], rate)
    counters[T] = t + 1
    if p.decay != CONSTANT:
        r = _scheduled(p.decay, p.radius, p.radius_final, t + 1, p.decay_steps)
        counters[TABLE_RADIUS] = int(math.floor(r + 0.5))
    return n, 0, 0, False
