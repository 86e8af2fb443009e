import functools

import pytest

from novelty import sonar


@functools.lru_cache(maxsize=None)
def _run(env: str, run: int, seed: int = 0):
    return sonar.simulate_run(env, seed, run)


@pytest.fixture(scope="session")
def sim():
    """simulate_run(env, seed, run), cached across the session (tests only read it)."""
    return _run
