"""Squared distances to every unit at once, in the project's summation order (shared by the kernels).

Weights are held transposed, (features, units), so that the loops over the
units are innermost and contiguous and vectorise. The order of the sums is
the one :mod:`novelty.distances` documents, so the distances equal
:func:`novelty.distances.squared_distances` bit for bit. Every function here is inlined
into the kernel that calls it (``inline="always"``), so importing this
module compiles nothing. numba keys a cached kernel on its own source file
only: after editing this file, clear the cache (``__pycache__/*.nb*`` or
``NUMBA_CACHE_DIR``) or the kernels keep the old code; an installed release
rewrites every file, which invalidates the cache.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: the units a vector holds (eight float64 in AVX-512): the distance loops run in whole vectors
#: over the columns a transposed copy has beyond its units, when it has them (the engine gives
#: its copy room in whole vectors, zero: ``novelty._kernels.engine.VECTOR``, kept equal)
VECTOR = 8


@njit(cache=True, error_model="numpy", inline="always")
def sq(WT, k, j, x):
    d = WT[k, j] - x[k]
    return d * d


@njit(cache=True, error_model="numpy", inline="always")
def block_cols(WT, x, out, acc, lo, n, n_units):
    """Sum of (WT[k, j] - x[k])**2 over the features k in [lo, lo + n), for every unit j.

    The project's order (:mod:`novelty.distances`): eight running sums over the
    blocks of eight features, combined pairwise, then the tail added one by one
    (fewer than eight features: all of them one by one). Starting a sum at 0.0 changes nothing
    (0.0 + s == s for the non-negative squares). The loops over units j are
    innermost and contiguous, so they vectorise. Up to 23 features (the
    paper's 16) the eight sums stay in registers, one pass over the units;
    beyond, they go through ``acc`` (8 x units), one pass per block of eight.
    Only the first ``n_units`` columns of ``WT`` are units (the others are room
    for a growing network).
    """
    end = lo + n - n % 8
    if 8 <= n < 16:
        for j in range(n_units):
            out[j] = ((sq(WT, lo, j, x) + sq(WT, lo + 1, j, x))
                      + (sq(WT, lo + 2, j, x) + sq(WT, lo + 3, j, x))) + (
                (sq(WT, lo + 4, j, x) + sq(WT, lo + 5, j, x))
                + (sq(WT, lo + 6, j, x) + sq(WT, lo + 7, j, x)))
    elif 16 <= n < 24:
        for j in range(n_units):
            r0 = sq(WT, lo, j, x) + sq(WT, lo + 8, j, x)
            r1 = sq(WT, lo + 1, j, x) + sq(WT, lo + 9, j, x)
            r2 = sq(WT, lo + 2, j, x) + sq(WT, lo + 10, j, x)
            r3 = sq(WT, lo + 3, j, x) + sq(WT, lo + 11, j, x)
            r4 = sq(WT, lo + 4, j, x) + sq(WT, lo + 12, j, x)
            r5 = sq(WT, lo + 5, j, x) + sq(WT, lo + 13, j, x)
            r6 = sq(WT, lo + 6, j, x) + sq(WT, lo + 14, j, x)
            r7 = sq(WT, lo + 7, j, x) + sq(WT, lo + 15, j, x)
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
def distances_cols(WT, x, acc, out, n_units):
    """Squared distances from ``x`` to the first ``n_units`` units, into ``out``.

    Weights as (features, units); ``acc`` (8, units) is scratch. Where ``WT``,
    ``out`` and ``acc`` have the columns, the units are counted up to a whole
    number of vectors (:data:`VECTOR`): the columns past ``n_units`` get values
    no one reads, and the loop no scalar remainder (a remainder taken one unit
    at a time was slower than one more vector: docs/guide/performance.md).
    """
    whole = min(n_units + (-n_units) % VECTOR, WT.shape[1], out.shape[0], acc.shape[1])
    if WT.shape[0] == 16:
        # The paper's 16 sonar readings: with the block size a constant, LLVM
        # drops the other cases and their checks (faster: docs/guide/performance.md).
        block_cols(WT, x, out, acc, 0, 16, whole)
    else:
        block_cols(WT, x, out, acc, 0, WT.shape[0], whole)


@njit(cache=True, error_model="numpy", inline="always")
def first_least(d, n):
    """The first index of the least of the squared distances ``d[:n]`` (``np.argmin``).

    Non-negative floats (no NaN, no -0.0: squared distances) order as their
    bits read as integers do, and integer minima vectorise (a float minimum
    would not, without fast-math): two vectorised passes instead of one
    comparison at a time, which halved the winner search of the online SOM
    (100 units); below 64 units the single pass is kept (faster there).
    """
    if n < 64:  # few units: one comparison at a time costs less than two passes
        s = 0
        for j in range(1, n):
            if d[j] < d[s]:
                s = j
        return s
    keys = d.view(np.int64)
    least = keys[0]
    for j in range(n):  # from 0, not 1: of 100 keys the vector loops take all, of 99 they left 3
        least = min(least, keys[j])
    first = n
    for j in range(n):
        first = min(first, j if keys[j] == least else n)
    return first


@njit(cache=True, error_model="numpy", inline="always")
def transposed(W, n_rows):
    """(features, units) copy of the first ``n_rows`` rows of ``W``, with W's rows of room."""
    WT = np.empty((W.shape[1], W.shape[0]))
    for j in range(n_rows):
        for k in range(W.shape[1]):
            WT[k, j] = W[j, k]
    return WT
