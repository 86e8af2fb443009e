"""Baseline tests fit many tiny models: one BLAS/OpenMP thread each is faster, and
keeps their run time steady on a busy two-core machine (threads oversubscribe)."""

import pytest
from threadpoolctl import threadpool_limits


@pytest.fixture(autouse=True)
def _one_thread():
    with threadpool_limits(limits=1):
        yield
