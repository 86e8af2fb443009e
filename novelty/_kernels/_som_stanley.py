"""Compiled learning and scoring loops for a SOM with Stanley synapses.

The reference is :func:`novelty.filter.learn_stream` driving
:class:`~novelty.clusterers.som.SOM` and
:class:`~novelty.habituation.stanley.StanleySynapse`. Every floating-point
operation below is written in the order numpy performs it there, so the
results are bit-identical, not merely close:

- numpy reduces ``((W - x) ** 2).sum(axis=1)`` by pairwise summation: eight
  running sums over blocks of eight features, combined as
  ``((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))``, the tail added one
  by one (fewer than eight features: one by one); more than 128 features are
  split in two halves (the first a multiple of eight) summed separately and
  added. :func:`._pairwise.pairwise_plan` lists those blocks,
  :func:`._distances.block_cols` sums one block in that order;
- the winner is the first unit with the least distance (``np.argmin``);
- the weight update is ``w + eta * (x - w)`` per element;
- the Euler step is :func:`~novelty.habituation.stanley.euler_steps`
  itself, compiled; the exact step
  ``y_inf + (y - y_inf) * exp(-alpha * dt / tau)``.

numba compiles without fast-math, so LLVM neither reorders these sums nor
fuses multiplies into adds. ``error_model="numpy"`` drops Python's
division-by-zero checks (the validated parameters never divide by zero).
This module imports numba; it is only imported through
:mod:`novelty._kernels`, on first use. No function here is recursive:
numba's on-disk cache does not handle recursion reliably.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..habituation.stanley import euler_steps
from ._distances import distances_cols, transposed, untransposed
from ._pairwise import pairwise_plan  # noqa: F401  (re-exported for callers)

# decay codes (SOM.decay)
CONSTANT, LINEAR, ASYMPTOTIC = 0, 1, 2


# ------------------------------------------------------ distances, transposed
@njit(cache=True, error_model="numpy", inline="always")
def _winner_cols(WT, x, plan, acc, stack):
    """Winner and its squared distance (the first of the least, as ``np.argmin``)."""
    n_units = WT.shape[1]
    distances_cols(WT, x, plan, acc, stack, n_units)
    d = stack[0]
    best = 0
    best_d = d[0]
    for j in range(1, n_units):
        if d[j] < best_d:
            best = j
            best_d = d[j]
    return best, best_d


# ---------------------------------------------------------------- the models
@njit(cache=True, error_model="numpy", inline="always")
def _scheduled(decay, start, final, t, steps):
    # SOM._scheduled, same operations
    if decay == CONSTANT:
        return start
    if decay == LINEAR:
        return start + (final - start) * min(t / steps, 1.0)
    return final + (start - final) / (1.0 + 2.0 * t / steps)


#: StanleySynapse._advance, method="euler": the reference's own function
_euler = njit(cache=True, error_model="numpy", inline="always")(euler_steps)


#: layout of the ``params`` vector of :func:`som_stanley_stream` (one array
#: instead of fifteen scalars: each argument costs time at every call)
PARAMS = ("n_columns", "decay", "learning_rate", "learning_rate_final", "radius",
          "radius_final", "decay_steps", "exact", "forget", "tau_winner",
          "tau_neighbour", "tau_forget", "alpha", "y0", "stimulus")


#: the one signature compiled (when this module is imported): callers pass
#: exactly these types, so no call ever triggers another compilation
SIGNATURE = (
    "UniTuple(int64, 2)(float64[:, ::1], float64[::1], float64[:, ::1], float64[::1], "
    "int64[::1], float64[::1], float64[::1], int64[:, ::1], float64[::1], boolean, int64, int64)"
)


@njit(SIGNATURE, cache=True, nogil=True, error_model="numpy")
def som_stanley_stream(W, y, X, dt, winners, novelty, distances, plan, params, learn,
                       table_radius, t):
    """Present the rows of ``X`` in order; write each one's winner, novelty and distance.

    The novelty is the winner's efficacy before the row is learned. With
    ``learn`` the weights ``W`` and efficacies ``y`` are updated in place
    (``learn_stream``); without, only the outputs are written (batch scoring
    and ``score_one``, for any clusterer whose winner is the nearest unit).
    ``params`` holds the values named in ``PARAMS``; ``table_radius`` is the
    grid radius of the SOM's neighbour table and ``t`` its update count, both
    returned as they are after the call.

    Scoring and learning share this one function so that numba compiles the
    distance code once (seconds of compiling per function on a fresh install).
    """
    n_units = W.shape[0]
    n_features = W.shape[1]
    n_columns = int(params[0])
    n_rows = n_units // n_columns
    decay = int(params[1])
    lr0, lr1, radius0, radius1, decay_steps = params[2], params[3], params[4], params[5], params[6]
    exact = params[7] != 0.0
    forget = params[8] != 0.0
    tau_w, tau_n, tau_f, alpha, y0, stimulus = (params[9], params[10], params[11], params[12],
                                                params[13], params[14])
    # Distances to all units vectorise on a transposed copy (features x
    # units); it is copied back at the end.
    WT = transposed(W, n_units)
    acc = np.empty((8, n_units))
    vstack = np.empty((plan.shape[0], n_units))
    radius = table_radius
    y_hit = y0 - stimulus / alpha  # efficacy approached under the stimulus
    y_rest = y0 - 0.0 / alpha  # and without it (forgetting)
    for i in range(X.shape[0]):
        x = X[i]
        winner, distance = _winner_cols(WT, x, plan, acc, vstack)
        winners[i] = winner
        novelty[i] = y[winner]
        distances[i] = distance
        if not learn:  # scoring: nothing below, not even dt, is read
            continue

        # The winner, its square grid neighbourhood (habituate with the
        # stimulus, adapt) and, when forgetting, every other unit (recover).
        # Each unit's update depends on that unit alone, so one pass in any
        # order reproduces Synapse.step followed by SOM.adapt.
        wr = winner // n_columns
        wc = winner - wr * n_columns
        r_lo = max(0, wr - radius)
        r_hi = min(n_rows - 1, wr + radius)
        c_lo = max(0, wc - radius)
        c_hi = min(n_columns - 1, wc + radius)
        h = dt[i]
        lr = _scheduled(decay, lr0, lr1, t, decay_steps)
        if exact:  # exp(-alpha * dt / tau) is shared by all units with the same tau
            fall_w = math.exp(-alpha * h / tau_w)
            fall_n = math.exp(-alpha * h / tau_n)
            fall_f = math.exp(-alpha * h / tau_f)
        else:
            fall_w = fall_n = fall_f = 0.0
        for r in range(0 if forget else r_lo, n_rows if forget else r_hi + 1):
            for c in range(0 if forget else c_lo, n_columns if forget else c_hi + 1):
                j = r * n_columns + c
                hit = r_lo <= r <= r_hi and c_lo <= c <= c_hi
                if not hit:
                    s, tau, fall, y_inf = 0.0, tau_f, fall_f, y_rest
                elif j == winner:
                    s, tau, fall, y_inf = stimulus, tau_w, fall_w, y_hit
                else:
                    s, tau, fall, y_inf = stimulus, tau_n, fall_n, y_hit
                if exact:
                    y[j] = y_inf + (y[j] - y_inf) * fall
                else:
                    y[j] = _euler(y[j], s, tau, h, alpha, y0)
                if hit:
                    for k in range(n_features):
                        WT[k, j] = WT[k, j] + lr * (x[k] - WT[k, j])
        t += 1
        if decay != CONSTANT:
            radius = int(math.floor(_scheduled(decay, radius0, radius1, t, decay_steps) + 0.5))
    if learn:
        untransposed(WT, W, n_units)
    return radius, t
