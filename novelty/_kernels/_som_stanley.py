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
  :func:`_block_cols` sums one block in that order;
- the winner is the first unit with the least distance (``np.argmin``);
- the weight update is ``w + eta * (x - w)`` per element;
- the Euler step is ``y + (h / tau) * (alpha * (y0 - y) - S)`` over
  ``ceil(dt)`` sub-steps; the exact step
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

from ._pairwise import pairwise_plan  # noqa: F401  (re-exported for callers)

# decay codes (SOM.decay)
CONSTANT, LINEAR, ASYMPTOTIC = 0, 1, 2


# ------------------------------------------------------ distances, transposed
@njit(cache=True, error_model="numpy", inline="always")
def _sq(WT, k, j, x):
    d = WT[k, j] - x[k]
    return d * d


@njit(cache=True, error_model="numpy", inline="always")
def _block_cols(WT, x, out, acc, lo, n):
    """Sum of (WT[k, j] - x[k])**2 over one block of at most 128 features k, for every unit j.

    numpy's order: eight running sums over the blocks of eight features,
    combined pairwise, then the tail added one by one (fewer than eight
    features: all of them one by one). Starting a sum at 0.0 changes nothing
    (0.0 + s == s for the non-negative squares). The loops over units j are
    innermost and contiguous, so they vectorise. Up to 23 features (the
    paper's 16) the eight sums stay in registers, one pass over the units;
    beyond, they go through ``acc`` (8 x units), one pass per block of eight.
    """
    n_units = WT.shape[1]
    end = lo + n - n % 8
    if 8 <= n < 16:
        for j in range(n_units):
            out[j] = ((_sq(WT, lo, j, x) + _sq(WT, lo + 1, j, x))
                      + (_sq(WT, lo + 2, j, x) + _sq(WT, lo + 3, j, x))) + (
                (_sq(WT, lo + 4, j, x) + _sq(WT, lo + 5, j, x))
                + (_sq(WT, lo + 6, j, x) + _sq(WT, lo + 7, j, x)))
    elif 16 <= n < 24:
        for j in range(n_units):
            r0 = _sq(WT, lo, j, x) + _sq(WT, lo + 8, j, x)
            r1 = _sq(WT, lo + 1, j, x) + _sq(WT, lo + 9, j, x)
            r2 = _sq(WT, lo + 2, j, x) + _sq(WT, lo + 10, j, x)
            r3 = _sq(WT, lo + 3, j, x) + _sq(WT, lo + 11, j, x)
            r4 = _sq(WT, lo + 4, j, x) + _sq(WT, lo + 12, j, x)
            r5 = _sq(WT, lo + 5, j, x) + _sq(WT, lo + 13, j, x)
            r6 = _sq(WT, lo + 6, j, x) + _sq(WT, lo + 14, j, x)
            r7 = _sq(WT, lo + 7, j, x) + _sq(WT, lo + 15, j, x)
            out[j] = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    elif n >= 24:
        for m in range(8):
            for j in range(n_units):
                acc[m, j] = 0.0
        for k in range(lo, end, 8):
            for m in range(8):
                xk = x[k + m]
                for j in range(n_units):
                    d = WT[k + m, j] - xk
                    acc[m, j] += d * d
        for j in range(n_units):
            out[j] = ((acc[0, j] + acc[1, j]) + (acc[2, j] + acc[3, j])) + (
                (acc[4, j] + acc[5, j]) + (acc[6, j] + acc[7, j]))
    else:
        for j in range(n_units):
            out[j] = 0.0
    for k in range(end, lo + n):
        xk = x[k]
        for j in range(n_units):
            d = WT[k, j] - xk
            out[j] += d * d


@njit(cache=True, error_model="numpy", inline="always")
def _winner_cols(WT, x, plan, acc, stack):
    """Winner and its squared distance, weights as (features, units).

    ``acc`` (8, units) and ``stack`` (plan length, units) are scratch.
    """
    if plan.shape[0] == 1 and plan[0, 1] == 16:
        # The paper's 16 sonar readings: with the block size a constant, LLVM
        # drops the other cases and their checks (about 1.4x faster).
        _block_cols(WT, x, stack[0], acc, 0, 16)
    else:
        sp = 0
        for p in range(plan.shape[0]):
            if plan[p, 1] > 0:
                _block_cols(WT, x, stack[sp], acc, plan[p, 0], plan[p, 1])
                sp += 1
            else:
                a = stack[sp - 2]
                b = stack[sp - 1]
                for j in range(WT.shape[1]):
                    a[j] = a[j] + b[j]
                sp -= 1
    d = stack[0]
    best = 0
    best_d = d[0]
    for j in range(1, WT.shape[1]):
        if d[j] < best_d:
            best = j
            best_d = d[j]
    return best, best_d


@njit(cache=True, error_model="numpy", inline="always")
def _transposed(W):
    WT = np.empty((W.shape[1], W.shape[0]))
    for j in range(W.shape[0]):
        for k in range(W.shape[1]):
            WT[k, j] = W[j, k]
    return WT


# ---------------------------------------------------------------- the models
@njit(cache=True, error_model="numpy", inline="always")
def _scheduled(decay, start, final, t, steps):
    # SOM._scheduled, same operations
    if decay == CONSTANT:
        return start
    if decay == LINEAR:
        return start + (final - start) * min(t / steps, 1.0)
    return final + (start - final) / (1.0 + 2.0 * t / steps)


@njit(cache=True, error_model="numpy", inline="always")
def _euler(y, stimulus, tau, dt, alpha, y0):
    # StanleySynapse._advance, method="euler": ceil(dt) equal sub-steps
    n_sub = max(1, math.ceil(dt))
    h = dt / n_sub
    for _ in range(n_sub):
        y = y + (h / tau) * (alpha * (y0 - y) - stimulus)
    return y


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
    WT = _transposed(W)
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
        # explicit loops: a slice assignment compiles numba's shape-error path (seconds)
        for j in range(n_units):
            for k in range(n_features):
                W[j, k] = WT[k, j]
    return radius, t
