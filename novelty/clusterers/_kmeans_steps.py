"""Online k-means in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

``state`` is ``(counts_,)``; ``p`` the vector of ``OnlineKMeans._kernel.params``
(a learning rate of 0 stands for ``"count"``, which no constant rate is).
"""

from __future__ import annotations

from .._jit import compiled, step
from ._graph_steps import nearest
from .base import move_towards
from .kmeans import OnlineKMeans

LR = OnlineKMeans._kernel.params.index("learning_rate")

_move = compiled(move_towards)


@step
def match(d, n, state, counters, p, nb):
    """The nearest unit; nothing learns with it (OnlineKMeans.match)."""
    return nearest(d, n), -1, 0


@step
def room(d, winner, n, state, counters, p):
    """k-means never grows."""
    return 0


@step
def adapt(WT, x, d, winner, runner_up, nb, k, n, state, counters, p, gone):
    """OnlineKMeans.adapt: the winner moves to the running mean of its inputs (or by a constant rate)."""
    counts = state[0]
    counts[winner] += 1
    rate = 1.0 / counts[winner] if p[LR] == 0.0 else p[LR]
    for f in range(WT.shape[0]):
        WT[f, winner] = _move(WT[f, winner], x[f], rate)
    return n, 0, 0, False
