"""Streams the clusterers' tests share: a robot's route and noisy traversals of it."""

import numpy as np
import pytest


def _corridor(seed, n_scans=200, n_sensors=16):
    """A robot's route as a smooth closed trajectory of 16 readings in [0.15, 0.85]."""
    rng = np.random.default_rng(seed)
    freq = rng.uniform(0.5, 2.0, size=n_sensors)
    phase = rng.uniform(0.0, 1.0, size=n_sensors)
    s = np.linspace(0.0, 1.0, n_scans)[:, None]
    return 0.5 + 0.35 * np.sin(2 * np.pi * (freq * s + phase))


def _traversals(route, n, rng, noise=0.01):
    """``n`` traversals of a route, each with fresh sensor noise."""
    return [np.clip(route + rng.normal(scale=noise, size=route.shape), 0.0, 1.0) for _ in range(n)]


@pytest.fixture
def corridor():
    """:func:`_corridor`: ``corridor(seed, n_scans=200, n_sensors=16)``."""
    return _corridor


@pytest.fixture
def traversals():
    """:func:`_traversals`: ``traversals(route, n, rng, noise=0.01)``."""
    return _traversals
