"""Rules for parameters and the check of a model's parameters against them.

Messages follow scikit-learn's form::

    The 'max_age' parameter of GrowingNeuralGas must be an int in [1, inf). Got 0 instead.
"""

from __future__ import annotations

import math
import numbers
import operator
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._messages import unknown_parameters

__all__ = ["Interval", "Options", "Instance", "Bounds", "validate_parameters", "unknown_parameters"]


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
        lo = "-inf" if self.low is None else _bound(self.low)
        hi = "inf" if self.high is None else _bound(self.high)
        lb = "[" if self.closed in ("both", "left") and self.low is not None else "("
        rb = "]" if self.closed in ("both", "right") and self.high is not None else ")"
        text = f"{what} in {lb}{lo}, {hi}{rb}"
        return text + (" or None" if self.allow_none else "")


def _bound(value) -> str:
    """A bound as a reader types it: a large power of two as ``2**53``, other numbers short."""
    if isinstance(value, int) and value > 2**20 and (value + 1) & value == 0:
        return f"2**{value.bit_length()} - 1"
    if isinstance(value, int) and value >= 2**20 and value & (value - 1) == 0:
        return f"2**{value.bit_length() - 1}"
    return f"{value:g}"


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

    A call on the hot path (every ``stream``) must cost little, and the
    parameters may have changed since the last call (``set_params``, or an
    attribute set directly): so the values that passed are remembered, per
    owner and set of rules, and a parameter is checked again unless it holds
    the very object that passed, of the same type, and either of a type whose
    value cannot change (a number, a string, None) or under a rule that reads
    only the type (:class:`Instance`). A list, for one, or any value under a
    rule of another kind, is checked every time.
    """
    if rules is None:
        rules = getattr(owner, "_parameter_rules", {})
    items = tuple(rules.items())
    values = tuple([getattr(owner, name) for name, _ in items])
    types = tuple(map(type, values))
    passed = _passed(owner, rules, items)
    if passed is not None and types == passed[1] and all(map(operator.is_, values, passed[0])):
        return
    for i, (name, rule) in enumerate(items):
        value = values[i]
        if passed is not None and value is passed[0][i] and types[i] is passed[1][i]:
            continue
        alternatives = rule if isinstance(rule, tuple) else (rule,)
        if not any(alt.accepts(value) for alt in alternatives):
            expected = " or ".join(alt.describe() for alt in alternatives)
            raise ValueError(
                f"The '{name}' parameter of {type(owner).__name__} must be {expected}. "
                f"Got {value!r} instead."
            )
    _remember(owner, rules, items, values, types)


#: types whose instances cannot change value: one that passed a rule passes it again
_IMMUTABLE = frozenset({int, float, str, bool, type(None), np.float64, np.float32, np.int64,
                        np.int32, np.bool_})
#: a stand-in, in the memory below, for a value that must be checked every time
_AGAIN = object()

#: per owner, held weakly (so that copies and pickles never carry it): the id of a rules
#: dict -> (its items, the values that passed, their types)
_memory: "weakref.WeakKeyDictionary[Any, dict]" = weakref.WeakKeyDictionary()


def _passed(owner: Any, rules: dict, items: tuple) -> tuple | None:
    try:
        entry = _memory.get(owner, {}).get(id(rules))
    except TypeError:  # an owner that cannot be weakly referenced or hashed
        return None
    if entry is None or entry[0] != items:  # another dict at that address, or the rules changed
        return None
    return entry[1:]


def _remember(owner: Any, rules: dict, items: tuple, values: tuple, types: tuple) -> None:
    kept = tuple(value if _stable(items[i][1], types[i]) else _AGAIN for i, value in enumerate(values))
    try:
        entries = _memory.setdefault(owner, {})
    except TypeError:
        return
    if len(entries) > 8:  # rules made afresh for each call: do not grow without bound
        entries.clear()
    entries[id(rules)] = (items, kept, types)


def _stable(rule, kind: type) -> bool:
    """Whether a value of type ``kind`` that passed ``rule`` passes it as long as it is the
    same object: an immutable value under this module's rules, or any value under rules
    that read only its type (a rule of another kind may read anything: never assumed)."""
    alternatives = rule if isinstance(rule, tuple) else (rule,)
    if all(type(alt) is Instance for alt in alternatives):
        return True
    return kind in _IMMUTABLE and all(type(alt) in (Interval, Options, Instance, Bounds)
                                      for alt in alternatives)


