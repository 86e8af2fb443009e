"""Stanley's synapse in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

The equations are :func:`~novelty.habituation.stanley.euler_steps` and
:func:`~novelty.habituation.stanley.exact_step`, compiled as they are;
:func:`advance` applies them to a set of units as ``StanleySynapse._advance``
does, and the schedule (:mod:`._schedule`) decides which units and when.
``state`` is ``(efficacy,)`` with room for more units; ``p`` is the
record of the synapse's parameters (``p.alpha``, ``p.y0``, ``p.method``).
"""

from __future__ import annotations

from .._jit import compiled, step as _step
from .._kernels.params import option_code
from .stanley import StanleySynapse, euler_steps, exact_step

EXACT = option_code(StanleySynapse, "method", "exact")

_euler = compiled(euler_steps)
_exact = compiled(exact_step)


@_step
def advance(state, rows, count, stimulus, tau, dt, p):
    """The efficacies of the units ``rows[:count]`` after ``dt`` (StanleySynapse._advance)."""
    y = state[0]
    exact = p.method == EXACT
    for m in range(count):
        j = rows[m]
        if exact:
            y[j] = _exact(y[j], stimulus, tau, dt, p.alpha, p.y0)
        else:
            y[j] = _euler(y[j], stimulus, tau, dt, p.alpha, p.y0)


@_step
def fresh(state, row, p):
    """An unhabituated synapse at ``row`` (Synapse._fresh)."""
    state[0][row] = p.y0
