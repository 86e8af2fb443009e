"""The compiled path of a component equals its readable reference (run through the conformance suite).

A component that declares compiled steps (``_kernel``, a
:class:`~novelty._component.KernelSpec`) promises that the filter's compiled
loop, composed with any partner that has compiled steps too, learns what the readable loop
(:func:`novelty._kernels.reference.learn_stream`) learns: the same novelty for every
scan and the same learned state, bit for bit, or within a tolerance the
component declares (``_kernel_tolerance``, a relative difference; 0 when it
does not declare one). A clusterer that declares ``"nearest-unit"``
(:func:`novelty._component.declares`) promises the same of batch scoring.

The check streams a drifting walk with irregular timestamps through a pair
that grows and prunes units: a synapse is paired with a Grow-When-Required
network that adds units and removes them (short edge ages), a clusterer with
a forgetting Stanley synapse. Without numba it is skipped
(``unittest.SkipTest``, which pytest reports as a skip).
"""

from __future__ import annotations

import unittest

import numpy as np
from sklearn.base import clone

from .._kernels import kernels_enabled, reference_loops, scorer, wait
from .._component import declares
from .._kernels.params import field_kind, spec_of
from ..clusterers.base import Clusterer
from ..clusterers.gwr import GrowWhenRequired
from ..filter import HabituatingFilter
from ..habituation.stanley import StanleySynapse
from ._helpers import _check, _data, _state_arrays

__all__ = ["check_compiled_equals_reference", "check_kernel_declares_every_parameter"]


def _pair(component) -> dict:
    if isinstance(component, Clusterer):
        return {"clusterer": clone(component), "synapse": StanleySynapse(others="forget")}
    grower = GrowWhenRequired(activity_threshold=0.9, max_age=6, habituation_threshold=0.3)
    return {"clusterer": grower, "synapse": clone(component)}


def _close(got, expected, tolerance: float, what: str) -> None:
    if tolerance == 0:
        np.testing.assert_array_equal(got, expected, err_msg=what)
    else:
        np.testing.assert_allclose(got, expected, rtol=tolerance, atol=0, err_msg=what)


@_check
def check_compiled_equals_reference(component) -> None:
    """The pair's compiled learning (and batch scoring, for a nearest-unit clusterer) equals
    the reference, with units added and removed on the way."""
    tolerance = float(type(component).__dict__.get("_kernel_tolerance", 0.0))
    X = _data(seed=3, n=240)
    dt = 1.0 + np.random.default_rng(3).integers(0, 3, len(X)) * 0.5  # gaps of 1, 1.5, 2 scans
    t = np.cumsum(dt)
    fast = HabituatingFilter(**_pair(component)).fit(X[:1], timestamps=t[:1])
    if not kernels_enabled():
        raise unittest.SkipTest("numba kernels unavailable")
    if spec_of(component) is not None:
        assert wait(fast.clusterer_, fast.synapse_) is not None, fast.compiled_
        assert fast.compiled_ == "compiled", fast.compiled_
    got = fast.stream(X[1:], timestamps=t[1:]), fast.novelty(X)
    with reference_loops():
        slow = HabituatingFilter(**_pair(component)).fit(X[:1], timestamps=t[:1])
        expected = slow.stream(X[1:], timestamps=t[1:]), slow.novelty(X)
    name = type(component).__name__
    _close(got[0], expected[0], tolerance, f"{name}: the novelty while learning")
    if declares(fast.clusterer_, "nearest-unit"):
        assert scorer(fast.clusterer_, fast.synapse_) is not None
    _close(got[1], expected[1], tolerance, f"{name}: the novelty after learning")
    fast_state, slow_state = _state_arrays(fast), _state_arrays(slow)
    assert fast_state.keys() == slow_state.keys(), f"{name}: the learned attributes differ"
    for key in slow_state:
        if slow_state[key].dtype.kind == "f":
            _close(fast_state[key], slow_state[key], tolerance, f"{name}: '{key}'")
        else:
            assert np.array_equal(fast_state[key], slow_state[key]), f"{name}: '{key}' differs"


@_check
def check_kernel_declares_every_parameter(component) -> None:
    """Every parameter reaches the compiled steps or is declared not to change what is learned,
    and every name the steps read has a field of their record ``p`` to hold it.

    A parameter reaches the steps when ``_kernel.params`` names it, or the value fitted from it
    (``name_``), or the base class reads it (a synapse's schedule); else ``_kernel.ignores``
    must name it (initialisation). Each name read needs a rule (:mod:`novelty.rules`), a
    declared fitted type (``KernelSpec.fitted``) or to be a nested component (``nested``).
    """
    cls, spec = type(component), spec_of(component)
    read = set(cls._kernel_base_params) | set(spec.params)
    unread = sorted(name for name in component.get_params(deep=False)
                    if name not in read and f"{name}_" not in read and name not in spec.ignores)
    assert not unread, (f"{cls.__name__}'s compiled steps never read {unread}: name them in "
                        "_kernel.params, or in _kernel.ignores if they do not change what is learned")
    both = sorted(set(spec.ignores) & read)
    assert not both, f"{cls.__name__}._kernel both reads and ignores {both}"
    typed = dict(spec.nested) | dict(spec.fitted)
    assert all(t in (float, int, bool) for t in dict(spec.fitted).values()), (
        f"{cls.__name__}._kernel.fitted: each type is float, int or bool")
    for name in cls._kernel_base_params + spec.params:
        if name not in typed:
            try:
                field_kind(cls, name)
            except TypeError as exc:
                raise AssertionError(str(exc)) from None
