"""Test-wide settings.

Tests fit many tiny models; one BLAS/OpenMP thread each is faster and keeps
run times steady on a busy two-core machine, where threads oversubscribe.
"""

import importlib.util

import pytest
from threadpoolctl import threadpool_limits

# The live node's rospy shell imports ROS 1's packages at its top (they come from the system's packages,
# not from pip): without them its doctests cannot be collected, and tests/rosnode skips with the reason.
collect_ignore = [] if importlib.util.find_spec("rospy") else ["novelty/rosnode/node.py"]


def pytest_configure(config):
    # Tests feed detectors scans of any scale on purpose; the warning for scans far outside
    # [0, 1] is for a user's data, and is tested where it is meant to fire. Named here, not in
    # pyproject.toml: this file is read with the checkout on the path, so the class named is
    # the checkout's, not that of an installed copy.
    config.addinivalue_line("filterwarnings", "ignore::novelty.ScanRangeWarning")
    # Likewise the advice to calibrate a threshold that does not carry over to new scans: tests
    # read thresholds of every detector on purpose; tests/test_conformal.py checks where it fires.
    config.addinivalue_line("filterwarnings", "ignore::novelty.conformal.CalibrationWarning")


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
