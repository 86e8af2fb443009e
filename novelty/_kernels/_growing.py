"""Compiled learning loops for the growing networks (GNG, GWR) with Stanley synapses.

The references are :func:`novelty.filter.learn_stream` driving
:class:`~novelty.clusterers.gng.GrowingNeuralGas` or
:class:`~novelty.clusterers.gwr.GrowWhenRequired` (whose firing counters are
a Stanley bank too) and :class:`~novelty.habituation.stanley.StanleySynapse`.
As in :mod:`._som_stanley`, the arithmetic is numpy's, operation by
operation, so the results are bit-identical (distances summed in numpy's
pairwise order, see :func:`._pairwise.pairwise_plan`); the one library
function involved, ``exp`` in the GWR's activity, is discussed where it is
used.

State lives in fixed-capacity arrays: ``W`` (capacity x features; the
kernel works on a transposed copy, so that distances vectorise), the
efficacies, the unit ids and the edge-age matrix ``A`` (capacity x capacity,
-1 = no edge), of which the first ``n`` rows are in use. Deleting units shifts
the later rows down, as ``np.delete`` does, so rows keep the reference's
numbering. A call stops early, returning the number of inputs it learned,
when the network is full and the next input might add a unit (GNG: an
insertion step; GWR: an input that will add one); the caller then enlarges
the arrays and calls again. So a call can also work on the network's own
arrays, without copies, until an input needs room.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..habituation.stanley import euler_steps
from ._distances import block_cols, transposed, untransposed

#: layout of a Stanley bank's parameter vector
STANLEY = ("exact", "forget", "tau_winner", "tau_neighbour", "tau_forget", "alpha", "y0")
GNG = ("epsilon_b", "epsilon_n", "insertion_interval", "insertion_error_decay", "error_decay",
       "max_age", "max_units")
GWR = ("activity_threshold_", "habituation_threshold", "epsilon_b", "epsilon_n", "max_age",
       "max_units", "firing_condition", "new_unit_wins")  # max_units < 0: no limit

_NO_EDGE = -1


# ----------------------------------------------------------------- distances
@njit(cache=True, error_model="numpy", inline="always")
def _two_nearest(WT, n, x, plan, acc, stack):
    """Winner, its squared distance and the runner-up (``argmin`` with the winner at inf)."""
    # numpy's order over the plan's blocks (as _distances.distances_cols, without
    # its 16-feature specialisation: that would make this module compile 1.5x longer)
    sp = 0
    for p in range(plan.shape[0]):
        if plan[p, 1] > 0:
            block_cols(WT, x, stack[sp], acc, plan[p, 0], plan[p, 1], n)
            sp += 1
        else:
            a = stack[sp - 2]
            b = stack[sp - 1]
            for j in range(n):
                a[j] = a[j] + b[j]
            sp -= 1
    d = stack[0]
    s1 = 0
    for j in range(1, n):
        if d[j] < d[s1]:
            s1 = j
    s2 = -1
    for j in range(n):
        if j != s1 and (s2 < 0 or d[j] < d[s2]):
            s2 = j
    if s2 < 0:
        s2 = 0
    return s1, d[s1], s2


# ------------------------------------------------------------ Stanley synapse
_euler = njit(cache=True, error_model="numpy", inline="always")(euler_steps)


@njit(cache=True, error_model="numpy", inline="always")
def _stanley_one(y, stimulus, tau, dt, exact, alpha, y0):
    # StanleySynapse._advance for one unit
    if exact:
        y_inf = y0 - stimulus / alpha
        return y_inf + (y - y_inf) * math.exp(-alpha * dt / tau)
    return _euler(y, stimulus, tau, dt, alpha, y0)


@njit(cache=True, error_model="numpy", inline="always")
def _stanley_step(y, n, winner, is_nb, stimulus, dt, p):
    """Synapse.step: the winner and the units with ``is_nb`` habituate, the others hold or recover."""
    exact = p[0] != 0.0
    forget = p[1] != 0.0
    for j in range(n):
        if j == winner:
            y[j] = _stanley_one(y[j], stimulus, p[2], dt, exact, p[5], p[6])
        elif is_nb[j]:
            y[j] = _stanley_one(y[j], stimulus, p[3], dt, exact, p[5], p[6])
        elif forget:
            y[j] = _stanley_one(y[j], 0.0, p[4], dt, exact, p[5], p[6])


# --------------------------------------------------------------------- graph
@njit(cache=True, error_model="numpy", inline="always")
def _mark_neighbours(A, n, row, is_nb):
    for j in range(n):
        is_nb[j] = A[row, j] >= 0


@njit(cache=True, error_model="numpy", inline="always")
def _age_edges(A, n, row):
    for j in range(n):
        if A[row, j] >= 0:
            A[row, j] += 1
            A[j, row] += 1


@njit(cache=True, error_model="numpy", inline="always")
def _connect(A, i, j, age):
    A[i, j] = age
    A[j, i] = age


@njit(cache=True, error_model="numpy", inline="always")
def _prune(A, n, row, max_age, isolated):
    """_graph.prune: drop the edges of ``row`` older than ``max_age``; mark the units left alone."""
    any_old = False
    for j in range(n):
        isolated[j] = False
        if A[row, j] > max_age:
            _connect(A, row, j, _NO_EDGE)
            isolated[j] = True  # a candidate for now
            any_old = True
    if not any_old:
        return 0
    isolated[row] = True
    count = 0
    for c in range(n):
        if isolated[c]:
            for j in range(n):
                if A[c, j] >= 0:
                    isolated[c] = False
                    break
            if isolated[c]:
                count += 1
    return count


@njit(cache=True, error_model="numpy", inline="always")
def _delete_units(n, gone, WT, A, ids, a, b, c):
    """np.delete of the units marked in ``gone`` from WT (columns), A (rows and columns), ids, a, b, c."""
    keep = 0
    for j in range(n):
        if gone[j]:
            continue
        if keep != j:
            for k in range(WT.shape[0]):  # element loops: slice assignment compiles slowly
                WT[k, keep] = WT[k, j]
            ids[keep] = ids[j]
            a[keep] = a[j]
            b[keep] = b[j]
            c[keep] = c[j]
            for i in range(n):
                A[keep, i] = A[j, i]
        keep += 1
    for i in range(keep):
        col = 0
        for j in range(n):
            if not gone[j]:
                A[i, col] = A[i, j]
                col += 1
    for i in range(keep):
        for j in range(keep, n):
            A[i, j] = _NO_EDGE
            A[j, i] = _NO_EDGE
    for j in range(keep, n):
        gone[j] = False
    return keep


@njit(cache=True, error_model="numpy", inline="always")
def _new_unit(n, A):
    for j in range(n + 1):
        A[n, j] = _NO_EDGE
        A[j, n] = _NO_EDGE


# ------------------------------------------------------------------- the GNG
@njit("int64[::1](float64[:, ::1], float64[::1], int32[:, ::1], float64[::1], int64[::1], "
      "float64[:, ::1], float64[::1], float64[::1], float64[::1], int64[:, ::1], float64[::1], "
      "float64[::1], float64, int64, int64, int64)", cache=True, nogil=True, error_model="numpy")
def gng_stream(W, E, A, y, ids, X, dt, novelty, distances, plan, g, p, stimulus, n, next_id,
               n_inputs):
    """Learn the rows of ``X`` with a GNG and a Stanley bank ``y`` (parameters ``g``, ``p``).

    Writes each row's novelty (the winner's efficacy) and squared distance to the winner.

    Returns ``[inputs learned, n units, next id, n_inputs]``; stops early
    when the arrays are full and the next input is an insertion step.
    """
    cap = W.shape[0]
    eps_b, eps_n, interval, ins_decay, err_decay = g[0], g[1], int(g[2]), g[3], g[4]
    max_age, max_units = int(g[5]), int(g[6])
    WT = transposed(W, n)  # (features, units): the distances vectorise; written back at the end
    acc = np.empty((8, cap))
    stack = np.empty((plan.shape[0], cap))
    is_nb = np.zeros(cap, dtype=np.bool_)
    gone = np.zeros(cap, dtype=np.bool_)
    dummy = np.empty(cap)
    done = 0
    for i in range(X.shape[0]):
        if n == cap and (n_inputs + 1) % interval == 0:
            break  # this input may insert a unit and there is no room: the caller makes some
        x = X[i]
        s1, d1, s2 = _two_nearest(WT, n, x, plan, acc, stack)
        novelty[i] = y[s1]
        distances[i] = d1
        _mark_neighbours(A, n, s1, is_nb)
        _stanley_step(y, n, s1, is_nb, stimulus, dt[i], p)
        # adapt, steps 3-9
        _age_edges(A, n, s1)
        E[s1] += d1  # ((x - w)**2).sum() is d1, the same numbers summed in the same order
        for k in range(WT.shape[0]):
            WT[k, s1] = WT[k, s1] + eps_b * (x[k] - WT[k, s1])
        for j in range(n):
            if is_nb[j]:
                for k in range(WT.shape[0]):
                    WT[k, j] = WT[k, j] + eps_n * (x[k] - WT[k, j])
        _connect(A, s1, s2, 0)
        if _prune(A, n, s1, max_age, gone) > 0:
            n = _delete_units(n, gone, WT, A, ids, E, y, dummy)
        n_inputs += 1
        if n_inputs % interval == 0 and n < max_units:
            q = 0
            for j in range(1, n):
                if E[j] > E[q]:
                    q = j
            f = -1
            for j in range(n):
                if A[q, j] >= 0 and (f < 0 or E[j] > E[f]):
                    f = j
            if f < 0:  # cannot happen after the first input: every unit has an edge
                untransposed(WT, W, n)
                return np.array([-1, n, next_id, n_inputs])
            E[q] *= ins_decay
            E[f] *= ins_decay
            for k in range(WT.shape[0]):
                WT[k, n] = 0.5 * (WT[k, q] + WT[k, f])
            E[n] = E[q]
            y[n] = p[6]
            ids[n] = next_id
            next_id += 1
            _new_unit(n, A)
            r = n
            n += 1
            _connect(A, q, f, _NO_EDGE)
            _connect(A, q, r, 0)
            _connect(A, r, f, 0)
        for j in range(n):
            E[j] *= 1.0 - err_decay
        done = i + 1
    untransposed(WT, W, n)
    return np.array([done, n, next_id, n_inputs])


# ------------------------------------------------------------------- the GWR
@njit("int64[::1](float64[:, ::1], float64[::1], int32[:, ::1], float64[::1], int64[::1], "
      "float64[:, ::1], float64[::1], float64[::1], float64[::1], int64[:, ::1], float64[::1], "
      "float64[::1], float64[::1], float64, int64, int64)", cache=True, nogil=True,
      error_model="numpy")
def gwr_stream(W, h, A, y, ids, X, dt, novelty, distances, plan, g, p, ph, stimulus, n, next_id):
    """Learn the rows of ``X`` with a GWR (counters ``h``, parameters ``ph``) and a Stanley bank ``y``.

    Writes each row's novelty and squared distance to the winner; with
    ``new_unit_wins``, a row that adds a unit has the new unit's fresh
    efficacy, and the new unit's synapse and counter fire for it.

    Returns ``[inputs learned, n units, next id]``; stops early when the
    arrays are full and the next input would add a unit.
    """
    cap = W.shape[0]
    a_t, h_t, eps_b, eps_n = g[0], g[1], g[2], g[3]
    max_age, max_units = int(g[4]), int(g[5])
    firing_condition, new_wins = g[6] != 0.0, g[7] != 0.0
    WT = transposed(W, n)  # (features, units): the distances vectorise; written back at the end
    acc = np.empty((8, cap))
    stack = np.empty((plan.shape[0], cap))
    is_nb = np.zeros(cap, dtype=np.bool_)
    gone = np.zeros(cap, dtype=np.bool_)
    dummy = np.empty(cap)
    done = 0
    for i in range(X.shape[0]):
        x = X[i]
        s, d_s, t = _two_nearest(WT, n, x, plan, acc, stack)
        # Step 7's test needs only d_s and h_s, which nothing changes before
        # step 7, so it is taken first: an input that adds a unit when there is
        # no room is left untouched for the caller, who makes room.
        # ((x - w_s)**2).sum() is d_s. sqrt is correctly rounded everywhere; exp
        # is the C library's here and numpy's in the reference: the same
        # function on x86-64 without AVX-512, where numpy uses its own SIMD exp
        # and the last bit may differ (it matters only at a_T exactly).
        activity = math.exp(-math.sqrt(d_s))
        grow = (activity < a_t and (h[s] < h_t or not firing_condition)
                and (max_units < 0 or n < max_units))
        if grow and n == cap:
            break
        novelty[i] = y[s]
        distances[i] = d_s
        _mark_neighbours(A, n, s, is_nb)
        is_nb[t] = True  # match(): the neighbours after step 5 include t
        _stanley_step(y, n, s, is_nb, stimulus, dt[i], p)
        # adapt, steps 5-11
        _connect(A, s, t, 0)
        r = n  # the new unit's row, if one is added
        if grow:
            for k in range(WT.shape[0]):
                WT[k, r] = 0.5 * (WT[k, s] + x[k])
            h[r] = ph[6]
            y[r] = p[6]
            if new_wins:  # Synapse.fire after the filter's bank has grown
                novelty[i] = y[r]
                y[r] = _stanley_one(y[r], stimulus, p[2], dt[i], p[0] != 0.0, p[5], p[6])
            ids[r] = next_id
            next_id += 1
            _new_unit(n, A)
            n += 1
            _connect(A, r, s, 0)
            _connect(A, r, t, 0)
            _connect(A, s, t, _NO_EDGE)
        else:
            for k in range(WT.shape[0]):
                WT[k, s] = WT[k, s] + eps_b * h[s] * (x[k] - WT[k, s])
            for j in range(n):
                if A[s, j] >= 0:
                    for k in range(WT.shape[0]):
                        WT[k, j] = WT[k, j] + eps_n * h[j] * (x[k] - WT[k, j])
        _age_edges(A, n, s)
        _mark_neighbours(A, n, s, is_nb)
        _stanley_step(h, n, s, is_nb, 1.0, 1.0, ph)
        if grow and new_wins:  # the new unit r fired too (GrowWhenRequired.adapt)
            h[r] = _stanley_one(h[r], 1.0, ph[2], 1.0, ph[0] != 0.0, ph[5], ph[6])
        if _prune(A, n, s, max_age, gone) > 0:
            n = _delete_units(n, gone, WT, A, ids, h, y, dummy)
        done = i + 1
    untransposed(WT, W, n)
    return np.array([done, n, next_id])
