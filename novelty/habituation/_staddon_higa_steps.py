"""Staddon & Higa's two-unit cascade in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

The equations are :func:`~novelty.habituation.staddon_higa.cascade_steps` (with
:func:`~novelty.habituation.staddon_higa.affine_power` for long gaps) and
:func:`~novelty.habituation.staddon_higa.efficacy`, compiled as they are;
:func:`advance` applies them unit by unit as ``StaddonHigaSynapse._advance``
does, and the schedule (:mod:`._schedule`) decides which units and when.
``state`` is ``(efficacy, fast_memory, slow_memory)``; ``p`` the record of the
synapse's parameters (``p.fast_gain``, ``p.slow_gain``, ``p.slowness``, ``p.y0``).
"""

from __future__ import annotations

from .._jit import compiled, step as _step
from . import staddon_higa as _model

_affine_power = compiled(_model.affine_power)
_cascade = compiled(_model.cascade_steps, affine_power=_affine_power)
_efficacy = compiled(_model.efficacy)


@_step
def advance(state, rows, count, stimulus, tau, dt, p):
    """The units ``rows[:count]`` after ``dt`` (StaddonHigaSynapse._advance)."""
    y, fast, slow = state[0], state[1], state[2]
    for m in range(count):
        j = rows[m]
        f, s = _cascade(fast[j], slow[j], stimulus, tau, dt, p.fast_gain, p.slow_gain, p.slowness)
        fast[j] = f
        slow[j] = s
        y[j] = _efficacy(f, s, p.y0)


@_step
def fresh(state, row, p):
    """An unhabituated synapse at ``row`` (StaddonHigaSynapse._fresh)."""
    state[0][row] = p.y0
    state[1][row] = 0.0
    state[2][row] = 0.0
