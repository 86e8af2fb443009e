"""Each scan's nearest unit, exactly as ``match`` finds it, from a float32 pre-filter.

The reference is ``Clusterer.match``: the squared distances
``d_j = ((W - x) ** 2).sum(axis=1)`` in float64, summed in numpy's pairwise
order, and the winner ``np.argmin(d)``, the first unit of least distance.
:func:`nearest` returns the same winner and the same ``d_winner``, bit for
bit, at a fraction of the cost:

1. **Pre-filter** (float32, vectorised over 128 scans at a time): for every
   unit ``j`` the expanded form ``s_j = |w_j|^2 - 2 x.w_j``, which differs
   from the squared distance by ``|x|^2``, the same for all units. Per scan
   the least value ``s_a`` (unit ``a``) and the second least ``s_b``.
2. **Decision**: if the gap ``s_b - s_a`` exceeds the bound ``T`` below, unit
   ``a`` is the reference's winner, and its distance is computed once, in
   float64 in numpy's order (:func:`_winner_distances`, vectorised over the
   scans). Otherwise (ties, near
   ties) every unit ``j`` with ``s_j <= s_a + T`` is a candidate (the others
   are farther than ``a``), the candidates' distances are computed in
   numpy's order (:func:`row_distance`) and the first of the least wins, as
   in the reference.
   Scans beyond float32's range (below) take the exact path: all distances
   in numpy's order (:func:`._distances.distances_cols`), the first of the
   least.

**The bound.** Let ``u = 2**-24`` (float32's unit roundoff), ``t = 2**-126``
(float32's smallest normal number: the absolute error of one rounding that
underflows, also with flush-to-zero), ``gamma_m(u) = m u / (1 - m u)``,
``n`` the number of features, ``r = |x| + max_j |w_j|``. Model every float32
operation (including the conversions of ``x`` and ``w``) as
``fl(v) = v (1 + delta) + eta``, ``|delta| <= u``, ``|eta| <= t``. Then
(Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., 2002,
section 3.1, for the dot product summed in any order):

- ``|p^ - x.w| <= gamma_{n+2}(u) sum_k |x_k w_k| + A/3 <= gamma_{n+2}(u) |x| |w| + A/3``
  for the float32 dot product ``p^`` of the rounded vectors (Cauchy-Schwarz);
- ``|n^_w - |w|^2| <= 2 u |w|^2 + t`` for ``|w|^2`` summed in float64 and
  rounded to float32;
- ``s^ = fl(n^_w - 2 p^)`` (doubling is exact), so
  ``|s^_j - (|w_j|^2 - 2 x.w_j)| <= gamma_{n+4}(u) (|w_j|^2 + 2 |x| |w_j|) + A
  <= e := gamma_{n+4}(u) r^2 + A``, with
  ``A = 3 t (sqrt(n) r + 2 n + 2)`` bounding every underflow term.

So ``D_j - D_a >= (s_j - s_a) - 2 e`` (the pre-filter's values ``s^`` written ``s``) for the exact squared distances
``D_j = |x - w_j|^2``. The reference's float64 distances are the exact ones
up to ``|d_j - D_j| <= gamma_{n+2}(2**-53) D_j`` (a rounded difference,
squared, then a sum of non-negative terms; float64 underflow is far below
``A``), and ``D_j <= r^2``. Hence ``s_j - s_a > T_0 := 2 e + 2 gamma_{n+2}(2**-53) r^2``
implies ``d_a < d_j``, strictly: such a unit ``j`` is not the winner, and
when it holds for all ``j != a`` (``s_b - s_a > T_0``) unit ``a`` is
``np.argmin(d)``. :func:`nearest` uses ``T = 2 T_0``; the factor 2 covers the
rounding of computing ``r``, ``T``, the gap and ``s_a + T`` in float64
(relative errors of order ``2**-50`` of ``r^2``, while ``T_0 >= 40 * 2**-24 r^2``).

float32 overflows beyond ``3.4e38``: when ``r > 1e18`` the products and sums
above might overflow, and the scan takes the exact path (every scan, when
``max_j |w_j| > 1e18``). The detectors accept scans of norm up to
:data:`novelty._validation.MAX_SCAN_NORM` (1e100); their float64 squared
distances stay finite.

numba compiles without fast-math, so the float64 sums keep numpy's order
(the float32 pre-filter may be summed in any order: the bound holds for all).
This module imports numba; :mod:`novelty._kernels` imports it on first use,
compiled in a child process like the other kernels. It is a little over 300
lines, a third of them the bound's derivation: kept whole so that a reader
checks the derivation against the code that relies on it in one place.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._distances import distances_cols, transposed

#: scans pre-filtered together, the lanes the loops over scans vectorise on (128
#: measured fastest of 16 to 512 with 16 features); fewer than LANES / 8 scans
#: (the end of a batch, ``score_one``) take the exact path, which costs less then
LANES = 128
#: float32: unit roundoff, and the absolute error of a rounding that underflows
U32 = 2.0**-24
TINY32 = 2.0**-126
#: float64 unit roundoff
U64 = 2.0**-53
#: the largest ``|x| + max |w|`` the float32 pre-filter takes: (1e18)^2 is far from float32's 3.4e38
LIMIT = 1e18

#: the one signature compiled: callers pass exactly these types
SIGNATURE = ("int64(float64[:, ::1], float64[::1], float64[:, ::1], int64[::1], float64[::1], "
             "float64[::1], int64[:, ::1])")


@njit(cache=True, error_model="numpy", inline="always")
def _sq(W, j, X, i, k):
    d = W[j, k] - X[i, k]
    return d * d


@njit(cache=True, error_model="numpy", inline="always")
def _block(W, j, X, i, lo, n):
    """Sum of (W[j, k] - X[i, k])**2 over one block [lo, lo + n) of at most 128 features, in
    numpy's pairwise order (as :func:`._distances.block_cols`, for one unit)."""
    end = lo + n - n % 8
    if n >= 8:
        r0, r1, r2, r3 = _sq(W, j, X, i, lo), _sq(W, j, X, i, lo + 1), _sq(W, j, X, i, lo + 2), \
            _sq(W, j, X, i, lo + 3)
        r4, r5, r6, r7 = _sq(W, j, X, i, lo + 4), _sq(W, j, X, i, lo + 5), _sq(W, j, X, i, lo + 6), \
            _sq(W, j, X, i, lo + 7)
        for k in range(lo + 8, end, 8):
            r0 += _sq(W, j, X, i, k)
            r1 += _sq(W, j, X, i, k + 1)
            r2 += _sq(W, j, X, i, k + 2)
            r3 += _sq(W, j, X, i, k + 3)
            r4 += _sq(W, j, X, i, k + 4)
            r5 += _sq(W, j, X, i, k + 5)
            r6 += _sq(W, j, X, i, k + 6)
            r7 += _sq(W, j, X, i, k + 7)
        res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    else:
        res = 0.0
    for k in range(end, lo + n):
        res += _sq(W, j, X, i, k)
    return res


@njit(cache=True, error_model="numpy", inline="always")
def row_distance(W, j, X, i, plan, stack):
    """``((W[j] - X[i]) ** 2).sum()`` bit for bit (``plan``: :func:`._pairwise.pairwise_plan`).

    Rows are passed by index: a view ``X[i]`` would count references to
    ``X`` (atomic operations) for every scan.
    """
    if plan.shape[0] == 1:
        return _block(W, j, X, i, 0, plan[0, 1])
    sp = 0
    for p in range(plan.shape[0]):
        if plan[p, 1] > 0:
            stack[sp] = _block(W, j, X, i, plan[p, 0], plan[p, 1])
            sp += 1
        else:
            stack[sp - 2] = stack[sp - 2] + stack[sp - 1]
            sp -= 1
    return stack[0]


@njit(cache=True, nogil=True, error_model="numpy")
def _prefilter(Wf, wn, XT, S, acc, s1, s2, arg):
    """For each lane b (a scan, as column ``XT[:, b]``): ``S[j, b] = wn[j] - 2 Wf[j].XT[:, b]``
    for every unit j, their least ``s1[b]`` and second least ``s2[b]``, and the first unit
    of the least ``arg[b]``.

    A function of its own (not inlined): in the caller's body LLVM vectorised
    it less well.
    """
    n_units, n = Wf.shape
    end8 = n - n % 8
    for b in range(LANES):
        s1[b] = np.inf
        s2[b] = np.inf
        arg[b] = 0
    for j in range(n_units):
        for b in range(LANES):
            acc[b] = 0.0
        # eight features at a time inside the loop over the lanes, so that
        # the lanes' sums are loaded and stored once per eight features
        for k in range(0, end8, 8):
            w0, w1, w2, w3 = Wf[j, k], Wf[j, k + 1], Wf[j, k + 2], Wf[j, k + 3]
            w4, w5, w6, w7 = Wf[j, k + 4], Wf[j, k + 5], Wf[j, k + 6], Wf[j, k + 7]
            for b in range(LANES):
                acc[b] += ((XT[k, b] * w0 + XT[k + 1, b] * w1)
                           + (XT[k + 2, b] * w2 + XT[k + 3, b] * w3)) + (
                    (XT[k + 4, b] * w4 + XT[k + 5, b] * w5)
                    + (XT[k + 6, b] * w6 + XT[k + 7, b] * w7))
        for k in range(end8, n):
            wk = Wf[j, k]
            for b in range(LANES):
                acc[b] += XT[k, b] * wk
        wj = wn[j]
        jj = np.int32(j)
        for b in range(LANES):  # least and second least, without branches
            v = wj - np.float32(2.0) * acc[b]
            S[j, b] = v
            arg[b] = jj if v < s1[b] else arg[b]
            s2[b] = min(s2[b], max(v, s1[b]))
            s1[b] = min(s1[b], v)


@njit(cache=True, nogil=True, error_model="numpy")
def _resolve(W, WT, y, X, start, m, lanes, norm, S, s1, s2, arg, near, w_max, plan, acc8, stack,
             one, winners, novelty, distances):
    """Winners of the scans ``start, ..., start + m - 1`` from the pre-filter's values
    (``lanes``: it ran, and ``near[b]`` is the distance to ``arg[b]``; else, or beyond its
    range, the exact path). Returns how many
    scans were re-checked (more than one candidate) or took the exact path."""
    n_units, n = W.shape
    g32 = (n + 4) * U32 / (1.0 - (n + 4) * U32)
    g64 = (n + 2) * U64 / (1.0 - (n + 2) * U64)
    root_n = math.sqrt(n)
    n_checked = 0
    for b in range(m):
        i = start + b
        r = norm[b] + w_max
        if not lanes or r > LIMIT:
            n_checked += 1
            a, best = _exact(WT, X, i, plan, acc8, stack)
        else:
            e = g32 * r * r + 3.0 * TINY32 * (root_n * r + 2.0 * n + 2.0)
            bound = 2.0 * (2.0 * e + 2.0 * g64 * r * r)
            a = arg[b]
            best = near[b]
            least = np.float64(s1[b])
            if np.float64(s2[b]) - least <= bound:
                # candidates: every unit within the bound of the least; the others are
                # farther than unit a. The first of the least exact distance among them.
                n_checked += 1
                limit = least + bound
                for j in range(n_units):
                    if j != a and np.float64(S[j, b]) <= limit:
                        d = row_distance(W, j, X, i, plan, one)
                        if d < best or (d == best and j < a):
                            a = j
                            best = d
        winners[i] = a
        novelty[i] = y[a]
        distances[i] = best
    return n_checked


@njit(cache=True, nogil=True, error_model="numpy")
def _winner_distances(W, XT64, arg, D, zero, plan, acc, stack):
    """Each lane's exact squared distance to its pre-filter winner, into ``stack[0]``.

    The differences ``W[arg[b], k] - x_b[k]`` (as ``match`` forms them), then
    :func:`._distances.distances_cols` with the lanes as its units and
    ``x = 0``: ``(d - 0.0)**2 == d * d`` exactly, so the sums are numpy's,
    vectorised over the lanes.
    """
    for k in range(W.shape[1]):
        for b in range(LANES):
            D[k, b] = W[arg[b], k] - XT64[k, b]
    distances_cols(D, zero, plan, acc, stack, LANES)


@njit(cache=True, nogil=True, error_model="numpy")
def _exact(WT, X, i, plan, acc8, stack):
    """What ``match`` does: all squared distances in numpy's order, the first of the least."""
    n_units = WT.shape[1]
    distances_cols(WT, X[i], plan, acc8, stack, n_units)
    best = stack[0, 0]
    a = 0
    for j in range(1, n_units):
        if stack[0, j] < best:
            a = j
            best = stack[0, j]
    return a, best


@njit(SIGNATURE, cache=True, nogil=True, error_model="numpy")
def nearest(W, y, X, winners, novelty, distances, plan):
    """Each row of ``X``: its nearest unit (row of ``W``), that unit's efficacy ``y`` and
    squared distance, written to ``winners``, ``novelty`` and ``distances``.

    Returns how many rows were re-checked or took the exact path (the gap test failed).
    """
    n_units, n = W.shape
    n_scans = X.shape[0]
    # float32 weights and squared norms, for the pre-filter
    Wf = np.empty((n_units, n), dtype=np.float32)
    wn = np.empty(n_units, dtype=np.float32)
    w_max = 0.0
    for j in range(n_units):
        s = 0.0
        for k in range(n):
            v = W[j, k]
            Wf[j, k] = np.float32(v)
            s += v * v
        wn[j] = np.float32(s)
        w_max = max(w_max, math.sqrt(s))
    # the exact path's scratch: transposed weights, as the learning kernels hold them
    WT = transposed(W, n_units)
    acc8 = np.empty((8, n_units))
    stack = np.empty((plan.shape[0], n_units))
    one = np.empty(plan.shape[0])
    # the pre-filter's lanes
    XT = np.zeros((n, LANES), dtype=np.float32)
    XT64 = np.zeros((n, LANES))
    D = np.empty((n, LANES))
    zero = np.zeros(n)
    acc_lanes = np.empty((8, LANES))
    near = np.empty((plan.shape[0], LANES))
    norm = np.zeros(LANES)
    S = np.empty((n_units, LANES), dtype=np.float32)
    acc = np.empty(LANES, dtype=np.float32)
    s1 = np.empty(LANES, dtype=np.float32)
    s2 = np.empty(LANES, dtype=np.float32)
    arg = np.empty(LANES, dtype=np.int32)
    prefilter = w_max <= LIMIT
    n_exact = 0
    for start in range(0, n_scans, LANES):
        m = min(LANES, n_scans - start)
        # a few scans (``score_one``) cost less on the exact path than a block of lanes
        lanes = prefilter and m * 8 >= LANES
        if lanes:
            for b in range(m):
                s = 0.0
                for k in range(n):
                    v = X[start + b, k]
                    XT[k, b] = np.float32(v)
                    XT64[k, b] = v
                    s += v * v
                norm[b] = math.sqrt(s)
            for b in range(m, LANES):  # a short last block: lanes of zeros, ignored
                for k in range(n):
                    XT[k, b] = 0.0
                    XT64[k, b] = 0.0
            _prefilter(Wf, wn, XT, S, acc, s1, s2, arg)
            _winner_distances(W, XT64, arg, D, zero, plan, acc_lanes, near)
        n_exact += _resolve(W, WT, y, X, start, m, lanes, norm, S, s1, s2, arg, near[0], w_max,
                            plan, acc8, stack, one, winners, novelty, distances)
    return n_exact
