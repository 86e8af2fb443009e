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


# Hypothesis: no per-example deadline (a loaded two-core machine makes timings
# meaningless; speed is measured in benchmarks/), and under CI a fixed example
# sequence, so that a run is reproducible from the commit alone.
try:
    import os

    from hypothesis import settings

    settings.register_profile("novelty", deadline=None)
    settings.register_profile("novelty-ci", deadline=None, derandomize=True)
    settings.load_profile("novelty-ci" if os.environ.get("CI") else "novelty")
except ImportError:  # hypothesis is a test extra
    pass
