import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))  # workers import 'toy' by this path

import toy  # noqa: E402

from .hand_rows import AUC, rows_of  # noqa: E402


@pytest.fixture
def rows():
    """The hand-made results table of :mod:`tests.bench.hand_rows`."""
    return rows_of(AUC)


@pytest.fixture
def toy_registered():
    """Register the toy task and the broken detector for one test, then remove them."""
    import novelty
    from novelty.datasets import registry as datasets

    datasets.register(toy.TASK, toy.toy_task, description="A tiny synthetic task (tests).", replace=True)
    novelty.register_detector(toy.BROKEN, toy.broken_detector, replace=True)
    yield toy
    datasets.unregister(toy.TASK)
    novelty.registry.detectors.unregister(toy.BROKEN)
