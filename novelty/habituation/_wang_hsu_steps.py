"""Wang & Hsu's synapse in the filter's compiled loop (see :mod:`novelty._kernels.drivers`).

The equations are the functions of :mod:`novelty.habituation.wang_hsu`
(``euler_advance``, ``exact_advance`` and the helpers they call), compiled as
they are: each advances a group of synapses together (the closed form of a
long gap depends on the whole group), so the units of a step are gathered
into a group, advanced and scattered back, as ``WangHsuSynapse._advance``
does; the schedule (:mod:`._schedule`) decides which units and when.
``state`` is ``(efficacy, recovery)``; ``p`` the record of the synapse's
parameters (``p.alpha``, ..., ``p.method``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .._jit import compiled, step as _step
from .._kernels.params import option_code
from . import wang_hsu as _model

EXACT = option_code(_model.WangHsuSynapse, "method", "exact")

_n_substeps = compiled(_model._n_substeps)
_level = compiled(_model.level)
_settled = compiled(_model.settled)
_recovery_step = compiled(_model.recovery_step)
_euler = compiled(_model.euler_advance, _n_substeps=_n_substeps, settled=_settled, level=_level)
_exact = compiled(_model.exact_advance, _n_substeps=_n_substeps, settled=_settled, level=_level,
                  recovery_step=_recovery_step)


@njit(cache=True, error_model="numpy")  # called at three places: inlined, it compiles slowly
def advance(state, rows, count, stimulus, tau, dt, p):
    """The units ``rows[:count]`` advanced together over ``dt`` (WangHsuSynapse._advance)."""
    y = np.empty(count)
    z = np.empty(count)
    for m in range(count):
        y[m] = state[0][rows[m]]
        z[m] = state[1][rows[m]]
    if p.method == EXACT:
        y, z = _exact(y, z, stimulus, tau, dt, p.alpha, p.beta, p.gamma, p.y0, p.l)
    else:
        y, z = _euler(y, z, stimulus, tau, dt, p.alpha, p.beta, p.gamma, p.y0, p.l)
    for m in range(count):
        state[0][rows[m]] = y[m]
        state[1][rows[m]] = z[m]


@_step
def fresh(state, row, p):
    """An unhabituated synapse at ``row`` (WangHsuSynapse._fresh)."""
    state[0][row] = p.y0
    state[1][row] = p.z0
