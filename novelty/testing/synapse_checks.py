"""The conformance checks every synapse model must pass (run through :mod:`novelty.testing.conformance`)."""

from __future__ import annotations

import numpy as np
from sklearn.base import clone

from ..habituation.base import Synapse
from ._helpers import _check

def _new_bank(s: Synapse, n: int = 6) -> Synapse:
    return clone(s).initialize(n)


@_check
def check_synapse_initialize(s: Synapse) -> None:
    bank = _new_bank(s)
    assert bank.efficacy_.shape == (6,)
    assert np.all(np.isfinite(bank.efficacy_))
    assert np.all(bank.efficacy_ == bank.efficacy_[0]), "fresh synapses are all alike"
    assert bank.resting_efficacy < bank.efficacy_[0], "habituation must lower the efficacy"


@_check
def check_synapse_habituates_and_is_bounded(s: Synapse) -> None:
    bank = _new_bank(s)
    start = bank.efficacy_[0]
    previous = start
    for _ in range(200):
        bank.step(0, np.array([1]))
        y = bank.efficacy_[0]
        assert y <= previous + 1e-12, "a constant stimulus must not raise the winner's efficacy"
        assert y >= bank.resting_efficacy - 1e-9, "efficacy must not fall below its resting value"
        previous = y
    assert bank.efficacy_[0] < start and bank.efficacy_[1] < start, "winner and neighbour habituate"
    assert abs(bank.efficacy_[0] - bank.resting_efficacy) < 1e-3, "a long stimulus reaches the resting value"


@_check
def check_synapse_hold_rule(s: Synapse) -> None:
    bank = _new_bank(clone(s).set_params(others="hold"))
    bank.step(0, np.array([1]))
    untouched = bank.efficacy_[2:].copy()
    for _ in range(5):
        bank.step(0, np.array([1]))
    assert np.array_equal(bank.efficacy_[2:], untouched), "with others='hold' other units keep their value"


@_check
def check_synapse_forget_rule(s: Synapse) -> None:
    bank = _new_bank(clone(s).set_params(others="forget"))
    for _ in range(10):
        bank.step(2, np.array([], dtype=np.intp))
    low = bank.efficacy_[2]
    for _ in range(10):
        bank.step(0, np.array([], dtype=np.intp))
    assert bank.efficacy_[2] > low, "with others='forget' an unstimulated synapse recovers"


@_check
def check_synapse_grow_shrink(s: Synapse) -> None:
    bank = _new_bank(s)
    for i in range(6):
        for _ in range(i):
            bank.step(i, np.array([], dtype=np.intp))
    before = bank.efficacy_.copy()
    bank.shrink(np.array([1, 4]))
    assert np.array_equal(bank.efficacy_, before[[0, 2, 3, 5]]), "shrink removes exactly the given rows"
    bank.grow(2)
    assert bank.n_units_ == 6 and np.all(bank.efficacy_[-2:] == clone(s).initialize(1).efficacy_[0])
    for name in type(bank)._per_unit:
        assert getattr(bank, name).shape[0] == 6, f"{name} must grow and shrink with the bank"


@_check
def check_synapse_dt(s: Synapse) -> None:
    small, big = _new_bank(s), _new_bank(s)
    small.step(0, np.array([], dtype=np.intp), dt=0.5)
    big.step(0, np.array([], dtype=np.intp), dt=2.0)
    assert big.efficacy_[0] < small.efficacy_[0], "a longer stimulus habituates more"
