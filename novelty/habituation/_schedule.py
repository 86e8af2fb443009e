"""The schedule of a synapse bank in the filter's compiled loop: who is stimulated, and when.

This is :meth:`Synapse.step <novelty.habituation.base.Synapse.step>` and
:meth:`Synapse.fire <novelty.habituation.base.Synapse.fire>` compiled, for
every synapse model: the model supplies only its equation, ``advance(state,
rows, count, stimulus, tau, dt, p)`` (the units ``rows[:count]`` integrated
over ``dt`` under a constant stimulus with time constant ``tau``; ``p`` its
parameters), passed in as ``advance``. The schedule's own parameters are the
base class's, fields of every synapse's record ``p``: ``p.tau_winner``,
``p.tau_neighbour``, ``p.others`` (the code of "hold" or of ``FORGET``) and
``p.tau_forget`` (``p.tau_neighbour`` when ``p.has_tau_forget`` is false, as
``Synapse.schedule`` resolves it).

The functions are inlined into the driver that calls them, where ``advance``
is a compile-time constant (a global of the driver's module).
"""

from __future__ import annotations

from .._jit import step as _step
from .._kernels.params import option_code
from .base import Synapse

FORGET = option_code(Synapse, "others", "forget")


@_step
def stimulate(advance, state, n, winner, nb, k, stimulus, dt, p, mark, rows):
    """Synapse.step: the other units (when forgetting) recover, the neighbours ``nb[:k]``
    habituate, then the winner. ``mark`` (all False) and ``rows`` are scratch of ``n`` items."""
    if p.others == FORGET:
        mark[winner] = True
        forget(advance, state, n, nb, k, dt, p, mark, rows)
        mark[winner] = False
    if k:
        advance(state, nb, k, stimulus, p.tau_neighbour, dt, p)
    fire(advance, state, winner, stimulus, dt, p, rows)


@_step
def fire(advance, state, row, stimulus, dt, p, rows):
    """Synapse.fire: the unit at ``row`` habituates alone, as a winner (``rows``: scratch)."""
    rows[0] = row
    advance(state, rows, 1, stimulus, p.tau_winner, dt, p)


@_step
def stimulate_rows(advance, state, n, winners, w, nb, k, stimulus, dt, p, mark, rows):
    """Synapse.step with several winners ``winners[:w]`` (a map's cells hit by one scan): the other units
    of the first ``n`` (when forgetting) recover, the neighbours ``nb[:k]`` habituate, then the winners.
    ``mark`` (all False) and ``rows`` are scratch of ``n`` items."""
    if p.others == FORGET:
        for m in range(w):
            mark[winners[m]] = True
        forget(advance, state, n, nb, k, dt, p, mark, rows)
        for m in range(w):
            mark[winners[m]] = False
    if k:
        advance(state, nb, k, stimulus, p.tau_neighbour, dt, p)
    if w:
        advance(state, winners, w, stimulus, p.tau_winner, dt, p)


@_step
def forget(advance, state, n, nb, k, dt, p, mark, rows):
    """The units of the first ``n`` neither marked (the winners) nor in ``nb[:k]`` recover (S = 0)."""
    for m in range(k):
        mark[nb[m]] = True
    count = 0
    for j in range(n):
        if not mark[j]:
            rows[count] = j
            count += 1
    for m in range(k):
        mark[nb[m]] = False
    if count:
        tau_forget = p.tau_forget if p.has_tau_forget else p.tau_neighbour
        advance(state, rows, count, 0.0, tau_forget, dt, p)
