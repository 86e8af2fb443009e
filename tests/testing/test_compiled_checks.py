"""The check that a component's compiled steps read every parameter, each from a field of ``p``,
fails for each way a declaration can fall short (the registered components pass it in
tests/testing/test_conformance.py)."""

from __future__ import annotations

import numbers

import numpy as np
import pytest

from novelty import KernelSpec, Synapse
from novelty.rules import Bounds, Interval
from novelty.testing import check_kernel_declares_every_parameter


class Leaky(Synapse):
    """A synapse with a rate the steps read and a range only its initialisation uses."""

    _parameter_rules = {"rate": Interval(numbers.Real, 0, 1), "span": Bounds()}
    _kernel = KernelSpec(steps="unused", params=("rate",), arrays=("efficacy_",), ignores=("span",))
    resting_efficacy = 0.5

    def __init__(self, rate=0.5, span=(0.0, 1.0)):
        self.rate, self.span = rate, span

    def _advance(self, rows, stimulus, tau, dt):
        pass

    def _fresh(self, n):
        return {"efficacy_": np.ones(n)}


def _declaring(**spec) -> Leaky:
    return type("Declared", (Leaky,), {"_kernel": KernelSpec(steps="unused", **spec)})()


def test_a_full_declaration_passes():
    check_kernel_declares_every_parameter(Leaky())


@pytest.mark.parametrize("spec, message", [
    ({"params": ()}, r"never read \['rate', 'span'\]"),
    ({"params": ("rate",)}, r"never read \['span'\]"),
    ({"params": ("rate", "span")}, "no record field holds a value of a Bounds rule"),
    ({"params": ("rate",), "ignores": ("rate", "span")}, r"both reads and ignores \['rate'\]"),
    ({"params": ("rate", "level_"), "ignores": ("span",)}, "'level_', which has no rule"),
    ({"params": ("rate", "level_"), "ignores": ("span",), "fitted": (("level_", str),)},
     "each type is float, int or bool"),
])
def test_what_the_steps_cannot_read_is_named(spec, message):
    with pytest.raises(AssertionError, match=message):
        check_kernel_declares_every_parameter(_declaring(**spec))


def test_a_fitted_value_stands_for_its_parameter():
    check_kernel_declares_every_parameter(
        _declaring(params=("rate_",), ignores=("span",), fitted=(("rate_", float),)))
