"""The schedule of a synapse bank in the filter's compiled loop: who is stimulated, and when.

This is :meth:`Synapse.step <novelty.habituation.base.Synapse.step>` and
:meth:`Synapse.fire <novelty.habituation.base.Synapse.fire>` compiled, for
every synapse model: the model supplies only its equation, ``advance(state,
rows, count, stimulus, tau, dt, p)`` (the units ``rows[:count]`` integrated
over ``dt`` under a constant stimulus with time constant ``tau``; ``p`` its
packed parameters), passed in as ``advance``. The schedule's own parameters
(``tau_winner``, ``tau_neighbour``, ``tau_forget``, ``others``) are the base
class's, handed over by name: ``tau_forget`` already resolved (``tau_neighbour``
when None) and ``forget`` true for ``others="forget"``.

The functions are inlined into the driver that calls them, where ``advance``
is a compile-time constant (a global of the driver's module).
"""

from __future__ import annotations

from .._jit import step as _step


@_step
def stimulate(advance, state, n, winner, nb, k, stimulus, dt, tau_winner, tau_neighbour,
              tau_forget, forget, p, mark, rows):
    """Synapse.step: the other units (when forgetting) recover, the neighbours ``nb[:k]``
    habituate, then the winner. ``mark`` (all False) and ``rows`` are scratch of ``n`` items."""
    if forget:
        mark[winner] = True
        for m in range(k):
            mark[nb[m]] = True
        count = 0
        for j in range(n):
            if not mark[j]:
                rows[count] = j
                count += 1
        for m in range(k):
            mark[nb[m]] = False
        mark[winner] = False
        if count:
            advance(state, rows, count, 0.0, tau_forget, dt, p)
    if k:
        advance(state, nb, k, stimulus, tau_neighbour, dt, p)
    fire(advance, state, winner, stimulus, dt, tau_winner, p, rows)


@_step
def fire(advance, state, row, stimulus, dt, tau_winner, p, rows):
    """Synapse.fire: the unit at ``row`` habituates alone, as a winner (``rows``: scratch)."""
    rows[0] = row
    advance(state, rows, 1, stimulus, tau_winner, dt, p)
