"""The self-check of the kernels' tricks (:mod:`.tricks`): each against its plain twin, in a child.

Run as ``python -c "from novelty._kernels import _probe; _probe.main()"`` with
``NOVELTY_KERNEL_TRICKS=1`` and ``NUMBA_NRT_STATS=1``: exit status 0 when
every check holds, 1 with the first failure on stderr. A crash (a
use-after-free, say) ends the child, not its parent, which then turns the
tricks off. The checks:

- :func:`._lanes.move_four_vector` against :func:`._lanes.move_four_plain` on a
  matrix of random, signed-zero, tiny and huge weights, for every count of
  lanes and neighbouring starts, bit for bit;
- a loop on :func:`._uncounted.uncounted_aliases` (of an argument, of local
  scratch, views of them, with allocations in the loop that would reuse
  freed memory) against the same loop on :func:`._uncounted.counted`, bit for
  bit; and numba's counts of allocations and frees balanced once the results
  are dropped (nothing leaked, nothing freed twice).
"""

from __future__ import annotations

import sys

import numpy as np
from numba import njit
from numba.core.runtime import rtsys

from ._lanes import move_four_plain, move_four_vector
from ._uncounted import counted, held, uncounted_aliases


@njit(error_model="numpy")
def _moves(WT, x, rates, vector):
    for f in range(WT.shape[0]):
        for j0 in range(WT.shape[1] - 3):
            count = (f + j0) % 5  # 0 to 4 lanes
            if vector:
                move_four_vector(WT, f, j0, x[f], rates[0], rates[1], rates[2], rates[3], count)
            else:
                move_four_plain(WT, f, j0, x[f], rates[0], rates[1], rates[2], rates[3], count)


@njit(error_model="numpy")
def _loop(X, n, aliased):
    out = np.zeros(n)
    acc = np.zeros(X.shape[1])
    owners = (out, acc, X)
    if aliased:
        a_out, a_acc, a_X = uncounted_aliases((out, acc, X))
    else:
        a_out, a_acc, a_X = counted((out, acc, X))
    for i in range(n):
        row = a_X[i % a_X.shape[0]]  # a view of an alias
        scratch = np.empty(a_acc.shape[0])  # fresh memory each scan, freed each scan
        for k in range(a_acc.shape[0]):
            scratch[k] = row[k] * (i + 1)
            a_acc[k] += scratch[k]
        a_out[i] = a_acc[i % a_acc.shape[0]] + scratch[0]
    held(owners)
    return out


def _check_moves() -> str | None:
    rng = np.random.default_rng(0)
    W = rng.normal(0.0, 1.0, (5, 11))
    W[0, :4] = [0.0, -0.0, 5e-324, 1e300]
    x = rng.normal(0.0, 1.0, 5)
    rates = np.array([0.25, 1.0, 0.0, 1.0 / 3.0])
    vector, plain = W.copy(), W.copy()
    _moves(vector, x, rates, True)
    _moves(plain, x, rates, False)
    if not np.array_equal(vector.view(np.int64), plain.view(np.int64)):
        return "move_four: the vector moved other values than the plain code"
    return None


def _check_aliases() -> str | None:
    X = np.random.default_rng(1).uniform(-1.0, 1.0, (7, 9))
    _loop(X, 3, True), _loop(X, 3, False)  # compiled before counting
    before = rtsys.get_allocation_stats()
    for n in (1, 50, 300):
        got, want = _loop(X, n, True), _loop(X, n, False)
        if not np.array_equal(got.view(np.int64), want.view(np.int64)):
            return f"uncounted aliases: a loop of {n} gave other values than the counted loop"
        del got, want
    after = rtsys.get_allocation_stats()
    if after.alloc - before.alloc != after.free - before.free:
        return (f"uncounted aliases: {after.alloc - before.alloc} allocations but "
                f"{after.free - before.free} frees")
    if after.mi_alloc - before.mi_alloc != after.mi_free - before.mi_free:
        return "uncounted aliases: memory owners allocated and freed unequally"
    return None


def main() -> None:
    """Run the checks; exit 1 with the first failure on stderr."""
    for check in (_check_moves, _check_aliases):
        failure = check()
        if failure is not None:
            print(failure, file=sys.stderr)
            sys.exit(1)
