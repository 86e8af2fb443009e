"""Stanley's synapse in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

The equations are :func:`~novelty.habituation.stanley.euler_steps` and
:func:`~novelty.habituation.stanley.exact_step`, compiled as they are; the
functions here apply them to the units as :meth:`Synapse.step` and
:meth:`Synapse.fire` do. ``state`` is ``(efficacy,)`` with room for more
units; ``p`` is the parameter vector of ``StanleySynapse._kernel.params``.
"""

from __future__ import annotations

import math

from .._jit import compiled, step as _step
from .stanley import StanleySynapse, euler_steps, exact_step

_P = StanleySynapse._kernel.params
TAU_W, TAU_N, TAU_F, ALPHA, Y0, OTHERS, METHOD = (
    _P.index(name) for name in ("tau_winner", "tau_neighbour", "tau_forget", "alpha", "y0",
                                "others", "method"))

_euler = compiled(euler_steps)
_exact = compiled(exact_step)


@_step
def advance(y, stimulus, tau, dt, p):
    """One unit's efficacy after ``dt`` (StanleySynapse._advance)."""
    if p[METHOD] != 0.0:  # "exact"
        return _exact(y, stimulus, tau, dt, p[ALPHA], p[Y0])
    return _euler(y, stimulus, tau, dt, p[ALPHA], p[Y0])


@_step
def step(state, n, winner, nb, k, stimulus, dt, p, mark):
    """Synapse.step: the winner and the neighbours ``nb[:k]`` habituate; the others hold or
    recover (``mark``: all False, scratch)."""
    y = state[0]
    if p[OTHERS] != 0.0:  # "forget"
        tau_f = p[TAU_N] if math.isnan(p[TAU_F]) else p[TAU_F]
        mark[winner] = True
        for m in range(k):
            mark[nb[m]] = True
        for j in range(n):
            if not mark[j]:
                y[j] = advance(y[j], 0.0, tau_f, dt, p)
        for m in range(k):
            mark[nb[m]] = False
        mark[winner] = False
    for m in range(k):
        j = nb[m]
        y[j] = advance(y[j], stimulus, p[TAU_N], dt, p)
    y[winner] = advance(y[winner], stimulus, p[TAU_W], dt, p)


@_step
def fire(state, row, stimulus, dt, p):
    """Synapse.fire: the unit at ``row`` habituates alone, as a winner."""
    state[0][row] = advance(state[0][row], stimulus, p[TAU_W], dt, p)


@_step
def fresh(state, row, p):
    """An unhabituated synapse at ``row`` (Synapse._fresh)."""
    state[0][row] = p[Y0]
