"""The order in which numpy sums: the plan both kernels follow (no numba here).

numpy reduces a contiguous row by pairwise summation: blocks of at most 128
items are summed with eight running sums (see the kernels), longer rows are
split in two halves, the first a multiple of eight items, summed separately
and added.
"""

from __future__ import annotations

import numpy as np

#: numpy's pairwise summation sums blocks of at most this many items directly
_PW_BLOCK = 128


def pairwise_plan(n_features: int) -> np.ndarray:
    """numpy's summation tree over ``n_features`` items, in post-order.

    Each row ``(lo, n)`` with ``n > 0`` sums the block ``[lo, lo + n)`` and
    pushes it; a row ``(0, 0)`` pops two partial sums and pushes their sum.
    Up to 128 features the plan is the single block ``(0, n_features)``.
    """
    ops: list[tuple[int, int]] = []
    pending = [(0, n_features, False)]
    while pending:  # iterative post-order walk of numpy's recursive split
        lo, n, expanded = pending.pop()
        if n <= _PW_BLOCK:
            ops.append((lo, n))
        elif expanded:
            ops.append((0, 0))
        else:
            half = n // 2
            half -= half % 8
            pending += [(lo, n, True), (lo + half, n - half, False), (lo, half, False)]
    return np.array(ops, dtype=np.int64)
