"""Test-wide settings.

Tests fit many tiny models; one BLAS/OpenMP thread each is faster and keeps
run times steady on a busy two-core machine, where threads oversubscribe.
"""

import pytest
from threadpoolctl import threadpool_limits


@pytest.fixture(autouse=True)
def _one_blas_thread():
    with threadpool_limits(limits=1):
        yield
