"""Data the baselines' tests share: three well-separated blobs and a point far from all of them."""

import numpy as np
import pytest


@pytest.fixture(scope="session")
def blobs():
    rng = np.random.default_rng(1)
    centres = np.array([[0.0, 0.0], [5.0, 0.0], [0.0, 5.0]])
    return np.vstack([rng.normal(c, 0.3, size=(120, 2)) for c in centres])


@pytest.fixture(scope="session")
def far():
    return np.array([[20.0, -20.0]])
