"""Each scan's nearest unit, exactly as ``match`` finds it, from a float32 pre-filter.

The reference is ``Clusterer.match``: the squared distances
``d_j = squared_distances(W, x)`` in float64, summed in the project's order
(:mod:`novelty.distances`), and the winner ``np.argmin(d)``, the first unit
of least distance.
:func:`nearest` returns the same winner and the same ``d_winner``, bit for
bit, at a fraction of the cost:

1. **Pre-filter** (float32, vectorised over 128 scans at a time): for every
   unit ``j`` the expanded form ``s_j = |w_j|^2 - 2 x.w_j``, which differs
   from the squared distance by ``|x|^2``, the same for all units. Per scan
   the least value ``s_a`` (unit ``a``) and the second least ``s_b``.
2. **Decision** (:func:`_decide`): the distance to unit ``a``, in float64
   in the project's order (:func:`row_distance`). If the gap ``s_b - s_a``
   exceeds the bound ``T`` below, unit ``a`` is the reference's winner and
   that is its distance. Otherwise (ties, near ties; in :func:`nearest`) every
   unit ``j`` with ``s_j <= s_a + T`` is a candidate (the others are farther
   than ``a``), the candidates' distances are computed in the project's
   order and the first of the least wins, as in the reference.
   Scans beyond float32's range (below) take the exact path: all distances
   in the project's order (:func:`._distances.distances_cols`), the first of
   the least.

**The bound.** Let ``u = 2**-24`` (float32's unit roundoff), ``t = 2**-126``
(float32's smallest normal number: the absolute error of one rounding that
underflows, also with flush-to-zero), ``gamma_m(u) = m u / (1 - m u)``,
``n`` the number of features, ``r = |x| + max_j |w_j|``. Model every float32
operation (including the conversions of ``x`` and ``w``) as
``fl(v) = v (1 + delta) + eta``, ``|delta| <= u``, ``|eta| <= t``; a fused
multiply-add ``fl(a b + c)`` rounds once. The pre-filter computes, for
each unit, ``s^ = c^ + sum_k x^_k m_k``: the ``n + 1`` terms summed in any
order, each product rounded once or fused with its addition, where
``x^_k = fl(x_k)``, ``m_k = -2 fl(w_k)`` (doubling is exact) and ``c^`` is
``|w|^2`` summed in float64 and rounded to float32. Then (Higham,
*Accuracy and Stability of Numerical Algorithms*, 2nd ed., 2002, section
3.1, for a sum of products in any order):

- ``|c^ - |w|^2| <= 2 u |w|^2 + t``, and
  ``|x^_k w^_k - x_k w_k| <= (2 u + u^2) |x_k w_k| + t (1 + u) (|x_k| + |w_k|) + t^2``;
- ``|s^ - (c^ + sum_k x^_k m_k)| <= gamma_{n+1}(u) (|c^| + 2 sum_k |x^_k w^_k|) + 2 n t (1 + gamma_n(u))``
  (``2 n`` roundings of products and sums, each at most ``t`` when it underflows);
- together, with ``sum_k |x_k w_k| <= |x| |w|`` and ``sum_k |x_k| <= sqrt(n) |x|``
  (Cauchy-Schwarz) and ``(1 + gamma_{n+1})(1 + gamma_3) <= 1 + gamma_{n+4}``:
  ``|s^_j - (|w_j|^2 - 2 x.w_j)| <= gamma_{n+4}(u) (|w_j|^2 + 2 |x| |w_j|) + A
  <= e := gamma_{n+4}(u) r^2 + A``, with
  ``A = 3 t (sqrt(n) r + 2 n + 2)`` bounding every underflow term (they sum
  to about ``t (2 sqrt(n) r + 2 n + 1)``).

So ``D_j - D_a >= (s_j - s_a) - 2 e`` (the pre-filter's values ``s^`` written ``s``) for the exact squared distances
``D_j = |x - w_j|^2``. The reference's float64 distances are the exact ones
up to ``|d_j - D_j| <= gamma_{n+2}(2**-53) D_j`` (a rounded difference,
squared, then a sum of ``n`` non-negative terms, whose error is at most
``gamma_{n-1}`` times the sum in every order of summation, so in the
project's (:mod:`novelty.distances`); float64 underflow is far below
``A``), and ``D_j <= r^2``. Hence ``s_j - s_a > T_0 := 2 e + 2 gamma_{n+2}(2**-53) r^2``
implies ``d_a < d_j``, strictly: such a unit ``j`` is not the winner, and
when it holds for all ``j != a`` (``s_b - s_a > T_0``) unit ``a`` is
``np.argmin(d)``. :func:`nearest` uses ``T = 2 T_0``; the factor 2 covers the
rounding of computing ``r``, ``T``, the gap and ``s_a + T`` in float64
(relative errors of order ``2**-50`` of ``r^2``, while ``T_0 >= 2 gamma_5(u) r^2 > 10 * 2**-24 r^2``).

float32 overflows beyond ``3.4e38``: when ``r > 1e18`` the products and sums
above might overflow, and the scan takes the exact path (every scan, when
``max_j |w_j| > 1e18``). The detectors accept scans of norm up to
:data:`novelty._validation.MAX_SCAN_NORM` (1e100); their float64 squared
distances stay finite.

numba compiles without fast-math, so the float64 sums keep the project's order;
the float32 pre-filter alone is compiled with fused multiply-adds
(:data:`PREFILTER_MATH`): the bound holds for every order and for fused or
separate products.
This module imports numba; :mod:`novelty._kernels` imports it on first use,
compiled in a child process like the other kernels. It is a little over 300
lines, a third of them the bound's derivation: kept whole so that a reader
checks the derivation against the code that relies on it in one place.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._validation.scans import CLEARED as _CLEARED, MAX_SCAN_NORM
from ._distances import distances_cols, first_least, transposed

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

#: the pre-filter's only fast-math flag: fused multiply-adds (each rounds once, within the
#: bound's model); no reassociation, no assumptions about infinities (its sums start at inf)
PREFILTER_MATH = {"contract"}
#: the one signature compiled: callers pass exactly these types
SIGNATURE = ("int64(float64[:, ::1], float64[::1], float64[:, ::1], int64[::1], float64[::1], "
             "float64[::1])")
#: :func:`nearest_one`'s
ONE_SIGNATURE = "int64(float64[:, ::1], float64[::1], int64, float64[::1], float64[::1])"
#: a scan's sum of squares at most this clears it of the norm bound (novelty._validation.scans)
CLEARED = _CLEARED


@njit(cache=True, error_model="numpy", inline="always")
def _sq(W, j, X, i, k):
    d = W[j, k] - X[i, k]
    return d * d


@njit(cache=True, error_model="numpy", inline="always")
def _block(W, j, X, i, lo, n):
    """Sum of (W[j, k] - X[i, k])**2 over the features [lo, lo + n), in the project's order
    (:mod:`novelty.distances`; as :func:`._distances.block_cols`, for one unit)."""
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
def row_distance(W, j, X, i):
    """:func:`novelty.distances.squared_distances` of ``W[j]`` and ``X[i]``, bit for bit.

    Rows are passed by index: a view ``X[i]`` would count references to
    ``X`` (atomic operations) for every scan.
    """
    if W.shape[1] == 16:  # the paper's 16 readings: a constant block, straight-line code
        return _block(W, j, X, i, 0, 16)
    return _block(W, j, X, i, 0, W.shape[1])


@njit(cache=True, error_model="numpy", inline="always")
def _aligned(rows, cols, like):
    """An empty (rows, cols) array of ``like``'s dtype starting on a 64-byte boundary.

    numba aligns its arrays to 32 bytes: a 64-byte vector load then splits
    across two cache lines in every other process (measured slower on the
    pre-filter's scratch: docs/guide/performance.md).
    """
    buf = np.empty(rows * cols + 64, like.dtype)  # 64 items: at least 64 bytes of room
    off = ((64 - buf.ctypes.data % 64) % 64) // buf.itemsize
    return buf[off:off + rows * cols].reshape((rows, cols))


@njit(cache=True, nogil=True, error_model="numpy")
def weights32(W):
    """The pre-filter's weights: ``-2 w`` in float32 (the doubling is exact), ``|w|^2``
    summed in float64 and rounded to float32, and ``max_j |w_j|`` (float64)."""
    n_units, n = W.shape
    f32 = np.empty(0, dtype=np.float32)
    Wm = _aligned(n_units, n, f32)
    wn = _aligned(1, n_units, f32)[0]
    w_max = 0.0
    for j in range(n_units):
        s = 0.0
        for k in range(n):
            v = W[j, k]
            Wm[j, k] = np.float32(-2.0) * np.float32(v)
            s += v * v
        wn[j] = np.float32(s)
        w_max = max(w_max, math.sqrt(s))
    return Wm, wn, w_max


@njit(cache=True, nogil=True, error_model="numpy", fastmath=PREFILTER_MATH)
def _prefilter(Wm, wn, XT, S, acc, s1, s2, arg):
    """For each lane b (a scan, as column ``XT[:, b]``): ``S[j, b] = wn[j] + Wm[j].XT[:, b]``
    (``Wm = -2 w``) for every unit j, their least ``s1[b]`` and second least ``s2[b]``, and
    the first unit of the least ``arg[b]``.

    A function of its own (not inlined): in the caller's body LLVM vectorised
    it less well; its fast-math flags (:data:`PREFILTER_MATH`) stay in it. No
    helper taking arrays is inlined into its loops: compiled in the process
    that runs it (not loaded from numba's cache) such a loop ran many times slower.
    """
    n_units, n = Wm.shape
    end8 = n - n % 8
    for b in range(LANES):
        s1[b] = np.inf
        s2[b] = np.inf
        arg[b] = 0
    for j in range(n_units):
        c = wn[j]
        for b in range(LANES):
            acc[b] = c
        # eight features at a time inside the loop over the lanes, so that
        # the lanes' sums are loaded and stored once per eight features
        for k in range(0, end8, 8):
            w0, w1, w2, w3 = Wm[j, k], Wm[j, k + 1], Wm[j, k + 2], Wm[j, k + 3]
            w4, w5, w6, w7 = Wm[j, k + 4], Wm[j, k + 5], Wm[j, k + 6], Wm[j, k + 7]
            for b in range(LANES):
                acc[b] += ((XT[k, b] * w0 + XT[k + 1, b] * w1)
                           + (XT[k + 2, b] * w2 + XT[k + 3, b] * w3)) + (
                    (XT[k + 4, b] * w4 + XT[k + 5, b] * w5)
                    + (XT[k + 6, b] * w6 + XT[k + 7, b] * w7))
        for k in range(end8, n):
            wk = Wm[j, k]
            for b in range(LANES):
                acc[b] += XT[k, b] * wk
        jj = np.int32(j)
        for b in range(LANES):  # least and second least, without branches
            v = acc[b]
            S[j, b] = v
            arg[b] = jj if v < s1[b] else arg[b]
            s2[b] = min(s2[b], max(v, s1[b]))
            s1[b] = min(s1[b], v)


@njit(cache=True, nogil=True, error_model="numpy", fastmath=PREFILTER_MATH)
def _prefilter16(Wm, wn, XT, S, acc, s1, s2, arg):
    """:func:`_prefilter` for the paper's 16 features: each lane's sum in registers
    (two chains of eight products), no pass through ``acc``; faster than the general loop."""
    n_units = Wm.shape[0]
    for b in range(LANES):
        s1[b] = np.inf
        s2[b] = np.inf
        arg[b] = 0
    for j in range(n_units):
        w0, w1, w2, w3 = Wm[j, 0], Wm[j, 1], Wm[j, 2], Wm[j, 3]
        w4, w5, w6, w7 = Wm[j, 4], Wm[j, 5], Wm[j, 6], Wm[j, 7]
        w8, w9, w10, w11 = Wm[j, 8], Wm[j, 9], Wm[j, 10], Wm[j, 11]
        w12, w13, w14, w15 = Wm[j, 12], Wm[j, 13], Wm[j, 14], Wm[j, 15]
        c = wn[j]
        jj = np.int32(j)
        for b in range(LANES):
            p = (c + XT[0, b] * w0 + XT[1, b] * w1 + XT[2, b] * w2 + XT[3, b] * w3
                 + XT[4, b] * w4 + XT[5, b] * w5 + XT[6, b] * w6 + XT[7, b] * w7)
            q = (XT[8, b] * w8 + XT[9, b] * w9 + XT[10, b] * w10 + XT[11, b] * w11
                 + XT[12, b] * w12 + XT[13, b] * w13 + XT[14, b] * w14 + XT[15, b] * w15)
            v = p + q  # least and second least, as in _prefilter
            S[j, b] = v
            arg[b] = jj if v < s1[b] else arg[b]
            s2[b] = min(s2[b], max(v, s1[b]))
            s1[b] = min(s1[b], v)


@njit(cache=True, error_model="numpy", inline="always")
def _bound(r, n):
    """The gap ``T = 2 T_0`` for ``r`` and ``n`` features (module docstring)."""
    g32 = (n + 4) * U32 / (1.0 - (n + 4) * U32)
    g64 = (n + 2) * U64 / (1.0 - (n + 2) * U64)
    e = g32 * r * r + 3.0 * TINY32 * (math.sqrt(n) * r + 2.0 * n + 2.0)
    return 2.0 * (2.0 * e + 2.0 * g64 * r * r)


@njit(cache=True, nogil=True, error_model="numpy")
def _decide(W, y, X, start, m, norm, w_max, s1, s2, arg, check, winners, novelty, distances):
    """Lanes ``0, ..., m - 1`` (scans ``start + b``): the pre-filter's winner, its exact
    distance and efficacy written out; ``check[b]`` where the gap test fails (or ``r`` is
    beyond :data:`LIMIT`). Returns how many fail.
    """
    n = W.shape[1]
    for b in range(m):  # the winner's distance, scan by scan (vectorised by features)
        distances[start + b] = row_distance(W, arg[b], X, start + b)
    n_check = 0
    for b in range(m):  # vectorised over the lanes
        r = norm[b] + w_max
        fail = (np.float64(s2[b]) - np.float64(s1[b]) <= _bound(r, n)) | (r > LIMIT)
        check[b] = fail
        n_check += fail
        a = arg[b]
        winners[start + b] = a
        novelty[start + b] = y[a]
    return n_check


@njit(cache=True, error_model="numpy", inline="always")
def _exact(WT, X, i, acc8, d):
    """What ``match`` does: all squared distances in the project's order, the first of the least."""
    n_units = WT.shape[1]
    distances_cols(WT, X[i], acc8, d, n_units)
    best = d[0]
    a = 0
    for j in range(1, n_units):
        if d[j] < best:
            a = j
            best = d[j]
    return a, best


@njit(SIGNATURE, cache=True, nogil=True, error_model="numpy")
def nearest(W, y, X, winners, novelty, distances):
    """Each row of ``X``: its nearest unit (row of ``W``), that unit's efficacy ``y`` and
    squared distance, written to ``winners``, ``novelty`` and ``distances``.

    Returns how many rows were re-checked or took the exact path (the gap test failed).
    """
    n_units, n = W.shape
    n_scans = X.shape[0]
    f32 = np.empty(0, dtype=np.float32)
    Wm, wn, w_max = weights32(W)
    # the exact path's scratch: transposed weights, as the learning kernels hold them
    WT = transposed(W, n_units)
    acc8 = np.empty((8, n_units))
    d_all = np.empty(n_units)
    # the pre-filter's lanes
    XT = _aligned(n, LANES, f32)
    XT[:] = 0.0
    S = _aligned(n_units, LANES, f32)
    acc = _aligned(1, LANES, f32)[0]
    s1 = _aligned(1, LANES, f32)[0]
    s2 = _aligned(1, LANES, f32)[0]
    arg = _aligned(1, LANES, np.empty(0, dtype=np.int32))[0]
    norm = np.empty(LANES)
    check = np.empty(LANES, dtype=np.bool_)
    prefilter = w_max <= LIMIT
    n_exact = 0
    for start in range(0, n_scans, LANES):
        m = min(LANES, n_scans - start)
        # a few scans (``score_one``) cost less on the exact path than a block of lanes
        if not (prefilter and m * 8 >= LANES):
            for i in range(start, start + m):
                n_exact += 1
                a, best = _exact(WT, X, i, acc8, d_all)
                winners[i] = a
                novelty[i] = y[a]
                distances[i] = best
            continue
        for b in range(m):
            s = 0.0
            for k in range(n):
                v = X[start + b, k]
                XT[k, b] = np.float32(v)
                s += v * v
            norm[b] = math.sqrt(s)
        for b in range(m, LANES):  # a short last block: lanes of zeros, ignored
            for k in range(n):
                XT[k, b] = 0.0
        if n == 16:
            _prefilter16(Wm, wn, XT, S, acc, s1, s2, arg)
        else:
            _prefilter(Wm, wn, XT, S, acc, s1, s2, arg)
        if _decide(W, y, X, start, m, norm, w_max, s1, s2, arg, check, winners, novelty,
                   distances) == 0:
            continue
        # The scans whose gap test failed. Within the pre-filter's range, every unit j
        # with S[j, b] <= s_a + T is a candidate (the others are farther than unit a);
        # their distances in the project's order, the first of the least. Beyond it, the exact
        # path. Written here, not in a function: a call passing these arrays cost
        # about as much as the re-check itself.
        for b in range(m):
            if check[b]:
                n_exact += 1
                i = start + b
                r = norm[b] + w_max
                if r > LIMIT:
                    a, best = _exact(WT, X, i, acc8, d_all)
                else:
                    a = arg[b]
                    best = distances[i]
                    limit = np.float64(s1[b]) + _bound(r, n)
                    for j in range(n_units):
                        if j != a and np.float64(S[j, b]) <= limit:
                            d = row_distance(W, j, X, i)
                            if d < best or (d == best and j < a):
                                a = j
                                best = d
                winners[i] = a
                novelty[i] = y[a]
                distances[i] = best
    return n_exact


@njit(cache=True, error_model="numpy", inline="always")
def units_cleared(d, n_units, total):
    """Whether the squared distances ``d[:n_units]`` from a scan whose sum of squares is
    ``total`` (at most :data:`CLEARED`) put every unit within the norm bound
    (:data:`novelty._validation.scans.MAX_SCAN_NORM`, which ``Clusterer._check_norm`` holds
    units to): the single-scan calls' check of the weights, one comparison a unit where a
    check of every value cost one per weight (a large share of a learning call).

    By the triangle inequality ``|w_j| <= |x| + sqrt(D_j)`` for the exact distance ``D_j``,
    so ``d_j <= (MAX - sqrt(total))^2 (1 - 1e-6)`` puts unit ``j`` within the bound: the
    computed ``d_j`` and ``total`` are within ``gamma_{n+2}(2**-53)`` of the exact ones
    (relative; below 1e-9, the reference's tolerance, up to 10^6 features), and the margin
    covers the few roundings of the limit. NaN and infinity in a unit make its distance NaN
    or infinite, which fail the comparison. A unit within the bound may fail it too (far from
    a scan near the bound): then the general path, whose exact checks decide.
    """
    room = MAX_SCAN_NORM - math.sqrt(total)
    limit = room * room * (1 - 1e-6)
    bad = 0  # a count, not a flag: LLVM vectorises it
    for j in range(n_units):
        bad += not d[j] <= limit
    return bad == 0


@njit(ONE_SIGNATURE, cache=True, nogil=True, error_model="numpy")
def nearest_one(WT, y, n_units, x, out):
    """One scan (``score_one``) against the weights as the learning engine holds them,
    transposed (``WT``: features, capacity), checked first as the learning driver checks a
    single scan: as many features as the units have and a sum of squares within
    :data:`CLEARED`; the units by their distances to it (:func:`units_cleared`). Then its
    nearest of the first ``n_units`` units, the distances to all of them at once in the
    project's order (vectorised over the units, as the learning driver computes them; no
    pre-filter: for one scan it costs more than it saves), the first of the least as
    ``match`` takes it: ``out`` receives ``[efficacy, squared distance, winner]``.

    Returns 0, or -1 (nothing written) when a check fails: the caller's general check then
    says why.
    """
    n = WT.shape[0]
    if x.shape[0] != n:
        return -1
    total = 0.0
    for k in range(n):
        total += x[k] * x[k]
    if not total <= CLEARED:
        return -1
    # as wide as WT: the distances run over whole vectors of its columns (distances_cols)
    d = np.empty(WT.shape[1])
    acc = np.empty((8, WT.shape[1]))
    distances_cols(WT, x, acc, d, n_units)
    if not units_cleared(d, n_units, total):
        return -1
    a = first_least(d, n_units)
    out[0] = y[a]
    out[1] = d[a]
    out[2] = a
    return 0
