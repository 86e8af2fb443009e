"""Rules for parameters and the check of a model's parameters against them.

Messages follow scikit-learn's form::

    The 'max_age' parameter of GrowingNeuralGas must be an int in [1, inf). Got 0 instead.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any

__all__ = ["Interval", "Options", "Instance", "Bounds", "validate_parameters"]


@dataclass(frozen=True)
class Interval:
    """A real or integer range; ``None`` bounds are infinite."""

    kind: type  # numbers.Integral or numbers.Real
    low: float | None = None
    high: float | None = None
    closed: str = "both"  # "both", "left", "right", "neither"
    allow_none: bool = False

    def accepts(self, value: Any) -> bool:
        if value is None:
            return self.allow_none
        if isinstance(value, bool) or not isinstance(value, self.kind):
            return False
        if isinstance(value, numbers.Real) and not math.isfinite(value) and value == value:
            # +-inf is only acceptable as an unbounded side, never as a value
            return False
        if value != value:  # NaN
            return False
        left_ok = self.low is None or (value >= self.low if self.closed in ("both", "left") else value > self.low)
        right_ok = self.high is None or (value <= self.high if self.closed in ("both", "right") else value < self.high)
        return left_ok and right_ok

    def describe(self) -> str:
        what = "an int" if self.kind is numbers.Integral else "a float"
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        lb = "[" if self.closed in ("both", "left") and self.low is not None else "("
        rb = "]" if self.closed in ("both", "right") and self.high is not None else ")"
        text = f"{what} in {lb}{lo}, {hi}{rb}"
        return text + (" or None" if self.allow_none else "")


@dataclass(frozen=True)
class Options:
    """One of a fixed set of values."""

    values: tuple

    def accepts(self, value: Any) -> bool:
        return isinstance(value, (str, bool, numbers.Number, type(None))) and value in self.values

    def describe(self) -> str:
        return "one of " + ", ".join(repr(v) for v in self.values)


@dataclass(frozen=True)
class Instance:
    """An instance of one of the given types (strings name registry entries)."""

    types: tuple
    description: str

    def accepts(self, value: Any) -> bool:
        return isinstance(value, self.types)

    def describe(self) -> str:
        return self.description


@dataclass(frozen=True)
class Bounds:
    """A pair ``(low, high)`` of finite real numbers (booleans are not numbers here), ``low < high``."""

    def accepts(self, value: Any) -> bool:
        finite = Interval(numbers.Real)
        return (isinstance(value, (tuple, list)) and len(value) == 2
                and all(finite.accepts(v) for v in value) and bool(value[0] < value[1]))

    def describe(self) -> str:
        return "a pair (low, high) of finite floats with low < high"


def validate_parameters(owner: Any, rules: dict | None = None) -> None:
    """Check every parameter of ``owner`` against ``rules`` (default: ``owner._parameter_rules``).

    Each rule is an :class:`Interval`, :class:`Options`, :class:`Instance`,
    :class:`Bounds` or a tuple of them (any may accept).
    """
    if rules is None:
        rules = getattr(owner, "_parameter_rules", {})
    for name, rule in rules.items():
        value = getattr(owner, name)
        alternatives = rule if isinstance(rule, tuple) else (rule,)
        if not any(alt.accepts(value) for alt in alternatives):
            expected = " or ".join(alt.describe() for alt in alternatives)
            raise ValueError(
                f"The '{name}' parameter of {type(owner).__name__} must be {expected}. "
                f"Got {value!r} instead."
            )
