"""What a component hands its compiled steps: its declaration, parameters and state arrays.

Everything here is read from the component's own :class:`~novelty._component.KernelSpec`
(``_kernel``, declared in the component's class body): no list of any
component's parameters lives in the kernels.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._component import Component, KernelSpec

__all__ = ["spec_of", "pack", "attribute", "arrays_of", "counters_of"]

#: parameter vectors by the values they pack (reading the values costs less than packing)
_packed: dict[tuple, np.ndarray] = {}


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


def _key(component, spec: KernelSpec) -> tuple:
    values = []
    for name in spec.params:
        value = attribute(component, name)
        if isinstance(value, Component):
            inner = spec_of(value)
            if inner is None:
                raise TypeError(f"{type(value).__name__} declares no kernel")
            value = (type(value), _key(value, inner))
        values.append(value)
    return type(component), tuple(values)


def _encode(component, name: str, value) -> list[float]:
    if isinstance(value, Component):
        return list(pack(value))
    if value is None:
        return [math.nan]
    if isinstance(value, (bool, np.bool_)):
        return [float(value)]
    if isinstance(value, str):
        rules = component._parameter_rules.get(name, ())
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
    components' vectors appended in place. Parameters may change between calls
    (``set_params``), so they are read every time."""
    spec = spec_of(component)
    key = _key(component, spec)
    vector = _packed.get(key)
    if vector is None:
        parts: list[float] = []
        for name in spec.params:
            parts += _encode(component, name, attribute(component, name))
        vector = np.array(parts, dtype=np.float64)
        if len(_packed) > 256:  # a parameter sweep: do not grow without bound
            _packed.clear()
        _packed[key] = vector
    return vector


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


def counters_of(component, spec: KernelSpec) -> np.ndarray | None:
    try:
        return np.array([int(getattr(component, name)) for name in spec.counters], dtype=np.int64)
    except (AttributeError, TypeError, ValueError, OverflowError):
        return None


def nested_ready(component, spec: KernelSpec) -> bool:
    """Whether every nested component declares the steps its owner drives it with."""
    for name, steps in spec.nested:
        inner = spec_of(getattr(component, name, None))
        if inner is None or inner.steps != steps:
            return False
    return True
