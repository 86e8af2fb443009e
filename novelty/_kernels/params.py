"""What a component hands its compiled steps: its declaration, parameters and state arrays.

Everything here is read from the component's own :class:`~novelty._component.KernelSpec`
(``_kernel``, declared in the component's class body) and parameter rules
(``_parameter_rules``): no list of any component's parameters lives in the kernels.

The parameters reach the steps as one record, ``p`` (a numpy structured array of one
element, a numba ``Record`` in the steps), with a named, typed field per parameter
(:func:`pack`); the rule of the parameter says which:

===================================================  ===========================================
the parameter takes                                  its fields
===================================================  ===========================================
an int (``Interval(numbers.Integral, ...)``)         ``name``: int64
a float (``Interval(numbers.Real, ...)``)            ``name``: float64
True or False (``Options((True, False))``)           ``name``: bool
one of some strings (``Options(("a", "b"))``)        ``name``: int64, the option's code
a number or one of some strings                      ``name``: the number (0 for a string), and
                                                     ``name_is_a``: bool, for each string
None too (``allow_none``, ``Options((None,))``)      also ``has_name``: bool (``name`` holds 0)
a value fitted from data (``KernelSpec.fitted``)     ``name``: its declared type
a nested component                                   ``name``: the nested component's own record
===================================================  ===========================================

So a step reads ``p.learning_rate``, ``p.neighbour_learning_rate if
p.has_neighbour_learning_rate else lr``, ``p.decay == LINEAR`` with ``LINEAR =
option_code(SOM, "decay", "linear")`` in its module (:func:`novelty.rules.option_code`),
``p.firing_.tau_winner``.
"""

from __future__ import annotations

import functools
import numbers
import operator
from typing import Callable

import numpy as np

from .._component import Component, KernelSpec
from .._validation import Interval, Options

__all__ = ["spec_of", "pack", "param_names", "option_code", "field_kind", "attribute", "arrays_of",
           "getter", "nested_ready"]


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


def param_names(component) -> tuple:
    """The names of the parameters the component's steps read: the base class's (a synapse's
    schedule, ``_kernel_base_params``), then its own class's ``_kernel.params``."""
    return type(component)._kernel_base_params + spec_of(component).params


def option_code(cls: type, name: str, option: str) -> int:
    """The int64 by which the steps of ``cls`` read ``option`` of the parameter ``name``: its
    position among the strings of the parameter's rule. A step module names each option it
    tests, ``LINEAR = option_code(SOM, "decay", "linear")``, and compares ``p.decay == LINEAR``
    (:mod:`novelty._kernels.params` tells which field holds each parameter)."""
    strings = field_kind(cls, name)[1]
    if option not in strings:
        raise ValueError(f"{option!r} is not an option of {cls.__name__}.{name}: {strings}")
    return strings.index(option)


def field_kind(cls: type, name: str) -> tuple:
    """``(number, strings, flag, none)`` of the parameter ``name`` of ``cls``, read from its
    rule: the type of the numbers it takes (``int``, ``float`` or None), the strings among
    its options, whether it takes True/False, whether it takes None."""
    rule = cls._parameter_rules.get(name)
    if rule is None:
        raise TypeError(f"{cls.__name__}._kernel names {name!r}, which has no rule "
                        "(_parameter_rules) and no declared type (KernelSpec.fitted)")
    number, strings, flag, none = None, [], False, False
    for alt in rule if isinstance(rule, tuple) else (rule,):
        if isinstance(alt, Interval):
            number = int if alt.kind is numbers.Integral and number is not float else float
            none = none or alt.allow_none
        elif isinstance(alt, Options):
            for v in alt.values:
                if v is None:
                    none = True
                elif isinstance(v, bool):
                    flag = True
                elif isinstance(v, str) and v.isidentifier():
                    strings.append(v)
                else:
                    raise TypeError(f"{cls.__name__}.{name}: the option {v!r} has no field type")
        else:
            raise TypeError(f"{cls.__name__}.{name}: no record field holds a value of a "
                            f"{type(alt).__name__} rule (declare it in KernelSpec.ignores)")
    if flag and (number is not None or strings):
        raise TypeError(f"{cls.__name__}.{name}: True/False mixed with other values")
    return number, tuple(strings), flag, none


def _fields(component, name: str, value) -> list[tuple[str, object, object]]:
    """The record fields ``(field, type, value)`` of one parameter (the module docstring's
    table)."""
    cls = type(component)
    if type(value) not in _SCALARS and isinstance(value, Component):
        if spec_of(value) is None:
            raise TypeError(f"{type(value).__name__} declares no kernel")
        packed = pack(value)
        return [(name, packed.dtype, packed[0])]
    fitted, number, strings, flag, none = _kind(cls, name)
    if fitted is not None:
        return [(name, _NUMPY[fitted], _convert(cls, name, fitted, value))]
    if isinstance(value, str) and value not in strings:
        raise ValueError(f"{cls.__name__}.{name} = {value!r} is not among its options")
    given = value is not None
    if number is not None:
        out = [(name, _NUMPY[number], _convert(cls, name, number, value)
                if given and not isinstance(value, str) else 0)]
        out += [(f"{name}_is_{s}", np.bool_, value == s) for s in strings]
    elif strings:
        out = [(name, np.int64, strings.index(value) if given else 0)]
    else:
        out = [(name, np.bool_, bool(value))]
    if none:
        out.append((f"has_{name}", np.bool_, given))
    return out


@functools.lru_cache(maxsize=1024)
def _kind(cls: type, name: str) -> tuple:
    """``(fitted type or None, *field_kind)`` of a parameter of ``cls``, read once: a class's
    rules and kernel declaration are its own, set in its body (reading them afresh was
    a large share of every engine made, which packs its parts' records)."""
    fitted = dict(cls.__dict__["_kernel"].fitted).get(name)
    return (fitted, None, (), False, False) if fitted is not None else (None, *field_kind(cls, name))


#: the types of the values a record field takes as they are (a nested component is none)
_SCALARS = frozenset({int, float, str, bool, type(None), np.float64, np.int64, np.bool_})

_NUMPY = {float: np.float64, int: np.int64, bool: np.bool_}


def _convert(cls: type, name: str, kind: type, value):
    try:
        converted = kind(value)
        if kind is int and not _INT64_MIN <= converted <= _INT64_MAX:
            raise OverflowError
        return converted
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{cls.__name__}.{name} = {value!r} is not {_WHAT[kind]} the compiled "
                         "steps can hold") from None


_INT64_MIN, _INT64_MAX = int(np.iinfo(np.int64).min), int(np.iinfo(np.int64).max)
_WHAT = {float: "a float", int: "an int64", bool: "a truth value"}


def pack(component) -> np.ndarray:
    """The component's parameters as its steps read them: a record (an array of one element)
    with one named, typed field per parameter (the module docstring's table), in the order of
    :func:`param_names`. (An engine packs again when a value changed.)"""
    names = param_names(component)
    fields = [f for name, value in zip(names, getter(names)(component))
              for f in _fields(component, name, value)]
    record = np.zeros(1, dtype=_record_type(tuple([(name, kind) for name, kind, _ in fields])))
    record[0] = tuple([value for _, _, value in fields])
    return record


@functools.lru_cache(maxsize=256)
def _record_type(fields: tuple) -> np.dtype:
    """The record's dtype of ``(field, type)`` pairs, made once for each (a dtype is slow to build)."""
    return np.dtype(list(fields), align=True)




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
