"""What a component hands its compiled steps: its declaration, parameters and state arrays.

Everything here is read from the component's own :class:`~novelty._component.KernelSpec`
(``_kernel``, declared in the component's class body): no list of any
component's parameters lives in the kernels.
"""

from __future__ import annotations

import math
import numbers
import operator
from typing import Callable

import numpy as np

from .._component import Component, KernelSpec

__all__ = ["spec_of", "pack", "attribute", "arrays_of", "getter", "nested_ready"]


def spec_of(component) -> KernelSpec | None:
    """The component's kernel declaration, if its own class makes one (a subclass may change
    the arithmetic: it runs the reference unless it declares a kernel itself)."""
    spec = type(component).__dict__.get("_kernel")
    return spec if isinstance(spec, KernelSpec) else None


def attribute(component, name: str):
    """``component.<name>``; a dotted name reaches into nested components."""
    if "." not in name:
        return getattr(component, name)
    for part in name.split("."):
        component = getattr(component, part)
    return component


def getter(names: tuple) -> Callable:
    """A function reading ``names`` (dotted names reach into nested components) of an object as
    a tuple, in one call (:func:`operator.attrgetter`)."""
    if len(names) == 1:
        one = operator.attrgetter(names[0])
        return lambda obj: (one(obj),)
    return operator.attrgetter(*names) if names else (lambda obj: ())


def _encode(component, name: str, value) -> list[float] | np.ndarray:
    if type(value) is float or type(value) is int:  # the common case first
        return [float(value)]
    if isinstance(value, Component):
        if spec_of(value) is None:
            raise TypeError(f"{type(value).__name__} declares no kernel")
        return pack(value)
    if value is None:
        return [math.nan]
    if isinstance(value, (bool, np.bool_)):
        return [float(value)]
    if isinstance(value, str):
        owner_path, _, leaf = name.rpartition(".")  # a dotted name: the nested component's rule
        owner = attribute(component, owner_path) if owner_path else component
        rules = owner._parameter_rules.get(leaf, ())
        for rule in rules if isinstance(rules, tuple) else (rules,):
            options = getattr(rule, "values", ())
            if value in options:
                return [float(options.index(value))]
        raise ValueError(f"{type(component).__name__}.{name} = {value!r} is not among its options")
    if isinstance(value, numbers.Real):
        return [float(value)]
    raise TypeError(f"{type(component).__name__}.{name} = {value!r} cannot be packed")


def pack(component) -> np.ndarray:
    """The float64 vector of the component's ``_kernel.params`` (see KernelSpec), nested
    components' vectors appended in place. (An engine packs again when a value changed.)"""
    spec = spec_of(component)
    parts: list[float] = []
    for name, value in zip(spec.params, getter(spec.params)(component)):
        parts.extend(_encode(component, name, value))
    return np.array(parts, dtype=np.float64)


def arrays_of(component, spec: KernelSpec, n_units: int) -> list | None:
    """The per-unit state arrays, or None when one is missing or not sized to ``n_units``."""
    out = []
    for name in spec.arrays:
        try:
            a = attribute(component, name)
        except AttributeError:
            return None
        if type(a) is not np.ndarray or a.shape[:1] != (n_units,) or a.dtype == object:
            return None
        if name in spec.square and a.shape != (n_units, n_units):
            return None
        out.append(a)
    return out


def nested_ready(component, spec: KernelSpec) -> bool:
    """Whether every nested component declares the steps its owner drives it with."""
    for name, steps in spec.nested:
        inner = spec_of(getattr(component, name, None))
        if inner is None or inner.steps != steps:
            return False
    return True
