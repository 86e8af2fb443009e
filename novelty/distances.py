"""Squared Euclidean distances in the project's own summation order (no numba here).

Every squared distance the filter compares, ranks or stores is summed in one
documented order, by this function in the readable code and by
:mod:`novelty._kernels._distances` and :mod:`novelty._kernels._nearest` in
the compiled code. So "exact" means: the compiled path does the same IEEE-754
float64 operations, in the same order, as :func:`squared_distances`; its
winners and distances equal the reference's bit for bit. It does not mean
that the sum is the correctly rounded value of the real distance, and it does
not depend on how numpy (or anything else) sums an array: only element-wise
subtractions, products and additions are used, each of which IEEE-754 rounds
the same way everywhere.

**The order.** For ``n`` features, with the squares ``q_k = (a_k - b_k)^2``
(the difference rounded, then its square rounded):

- ``n < 8``: ``((q_0 + q_1) + q_2) + ...``, left to right;
- ``n >= 8``: eight running sums ``s_m = ((q_m + q_{m+8}) + q_{m+16}) + ...``
  over the features ``k = m (mod 8)`` below ``e = n - n mod 8``, combined as
  ``((s_0 + s_1) + (s_2 + s_3)) + ((s_4 + s_5) + (s_6 + s_7))``, then the
  last ``n mod 8`` squares added one by one, in order.

Up to 128 features this is also the order of numpy's pairwise summation
(``((a - b) ** 2).sum(axis=1)`` gives the same bits there today); beyond,
numpy splits the features into halves and ours does not. Eight independent
sums let the compiled loops keep eight accumulators in flight.

**Rounding.** Each sum is a recursive sum of non-negative terms, so the
computed value ``d`` is within ``gamma_{n+2}(2**-53) * D`` of the exact
``D = |a - b|^2`` (Higham 2002, section 4.2: every order of summation of
``n`` terms has error at most ``gamma_{n-1}`` times the sum of their
magnitudes; the rounded difference and its square add three roundings). The
float32 pre-filter of batch scoring relies on that bound only
(:mod:`novelty._kernels._nearest`).

References
----------
Higham, N. J. (2002). *Accuracy and Stability of Numerical Algorithms*, 2nd
ed., SIAM, chapter 4 (summation).
"""

from __future__ import annotations

import numpy as np

__all__ = ["squared_distances", "sum_of_squares_rows"]

#: the number of running sums of the order (see the module docstring)
LANES = 8


def squared_distances(a, b) -> np.ndarray:
    """``|a_i - b_i|^2`` for each row, in the project's summation order (module docstring).

    ``a`` and ``b`` broadcast against each other as numpy arrays do: the
    weights ``W`` (units, features) and one scan ``x`` give each unit's
    squared distance to ``x``; two vectors give a 0-d array.

    >>> import numpy as np
    >>> float(squared_distances(np.array([1.0, 2.0]), np.array([0.0, 0.0])))
    5.0
    """
    diff = np.subtract(a, b, dtype=np.float64)
    np.multiply(diff, diff, out=diff)
    return sum_of_squares_rows(diff)


def sum_of_squares_rows(q: np.ndarray) -> np.ndarray:
    """The sums of the last axis of ``q`` (the squares), in the project's order."""
    n = q.shape[-1]
    if n < LANES:
        out = np.array(q[..., 0], dtype=np.float64, copy=True)
        for k in range(1, n):
            out += q[..., k]
        return out
    end = n - n % LANES
    sums = q[..., 0:LANES] + q[..., LANES:2 * LANES] if end >= 2 * LANES else q[..., 0:LANES].copy()
    for k in range(2 * LANES, end, LANES):
        sums += q[..., k:k + LANES]
    pairs = sums[..., 0::2] + sums[..., 1::2]  # (s0 + s1), (s2 + s3), (s4 + s5), (s6 + s7)
    quads = pairs[..., 0::2] + pairs[..., 1::2]
    out = np.asarray(quads[..., 0] + quads[..., 1])
    for k in range(end, n):
        out += q[..., k]
    return out
