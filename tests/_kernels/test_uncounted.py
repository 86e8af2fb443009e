"""Uncounted aliases (novelty._kernels._uncounted): the same memory, nothing leaked or freed early."""

from __future__ import annotations

import numpy as np
import pytest

from novelty import _kernels

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


@pytest.fixture(scope="module")
def loop():
    """A loop on uncounted aliases of a local array and of an argument, as a driver's."""
    from numba import njit

    from novelty._kernels._uncounted import held, uncounted_aliases

    @njit
    def run(x, n):
        out = np.zeros(x.shape[0])
        owners = (out, x)
        local, y, k = uncounted_aliases((out, x, 3))  # the int passes as it is
        for i in range(n):
            row = y[i % y.shape[0]:]  # a view of an alias: uncounted too
            local[i % local.shape[0]] += row[0] * k
        held(owners)
        return out  # the owner: an alias must not outlive the call

    return run


def test_uncounted_aliases_share_the_memory_and_free_it_once(loop):
    from numba.core.runtime import _nrt_python, rtsys

    x = np.arange(5.0)
    loop(x, 1)  # compiled before counting
    _nrt_python.memsys_enable_stats()  # numba's counts of allocations (off unless asked for)
    before = rtsys.get_allocation_stats()
    out = loop(x, 12)
    np.testing.assert_array_equal(out, [0.0, 9.0, 12.0, 18.0, 24.0])  # 3 x[j], added 3, 3, 2, 2, 2 times
    during = rtsys.get_allocation_stats()
    del out
    after = rtsys.get_allocation_stats()
    # the returned array alone still held after the call; everything freed once it goes
    assert (during.alloc - before.alloc) - (during.free - before.free) == 1
    assert after.alloc - before.alloc == after.free - before.free >= 1
    assert after.mi_alloc - before.mi_alloc == after.mi_free - before.mi_free
    _nrt_python.memsys_disable_stats()
