"""What the conformance checks share: their data, a component's learned state, the check marker."""

from __future__ import annotations

from typing import Callable

import numpy as np

N_FEATURES = 5


def _data(seed: int = 0, n: int = 120, n_features: int = N_FEATURES) -> np.ndarray:
    """A smooth random walk in [0, 1]^d, like a robot's consecutive sonar scans."""
    rng = np.random.default_rng(seed)
    steps = rng.normal(scale=0.08, size=(n, n_features))
    return np.clip(0.5 + np.cumsum(steps, axis=0), 0.0, 1.0)


def _rows(component, seed: int = 0, n: int = 120) -> np.ndarray:
    """Rows ``component`` reads: :func:`_data`, or its own example where it reads a layout of its own.

    A detector that reads rows of a stated layout (``input_layout``, e.g. the
    ``points`` input of :mod:`novelty.io.scans.points`) gives example rows of it
    (``_example_rows(seed, n)``) for the checks.
    """
    if getattr(component, "input_layout", None) is not None:
        return np.asarray(type(component)._example_rows(seed, n), dtype=np.float64)
    return _data(seed, n)


def _state_arrays(obj) -> dict[str, np.ndarray]:
    """Every learned array of ``obj`` and of its nested components, by path."""
    arrays, values, children = obj._export_state()
    out = {name: np.array(a, copy=True) for name, a in arrays.items()}
    out.update({f"value:{k}": np.array(repr(v)) for k, v in values.items()})
    for name, child in children.items():
        out.update({f"{name}/{k}": v for k, v in _state_arrays(child).items()})
    return out


def _assert_same_state(before: dict, after: dict, what: str) -> None:
    assert before.keys() == after.keys(), f"{what}: the set of learned attributes changed"
    for key in before:
        assert np.array_equal(before[key], after[key]), f"{what}: '{key}' changed"


def _check(fn: Callable) -> Callable:
    fn.__conformance__ = True
    return fn
