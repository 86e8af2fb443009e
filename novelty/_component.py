"""The small base shared by every component: parameters and learned state.

Parameters follow scikit-learn's contract (``__init__`` stores its arguments
unchanged; :meth:`get_params` reads the signature). Learned state is every
public attribute whose name ends in ``_``; :meth:`Component._export_state`
and :meth:`Component._import_state` move it in and out as plain arrays and
JSON values, which is what model files hold (never pickle).
"""

from __future__ import annotations

import numbers
from typing import Any, NamedTuple

import numpy as np
from sklearn.base import BaseEstimator

from ._validation import validate_parameters

__all__ = ["Component", "FittedPartError", "KernelSpec", "StateError", "declares", "held_by_engine",
           "engine_writes"]

#: the capabilities a component class may declare (``_capabilities``), and what each promises
CAPABILITIES = {
    "nearest-unit": "a clusterer whose winner, in match and winners alike, is the first unit of "
                    "least novelty.distances.squared_distances(weights_, x): batch scoring is "
                    "then compiled (the nearest-unit kernel) for it, with any synapse",
    "several-winners": "a clusterer whose units are the world's cells (novelty.maps.cells): a scan wins every "
                       "cell its echoes fall in; it composes with a synapse in novelty.maps.HabituatingMap",
}


def declares(component, capability: str) -> bool:
    """Whether the component's own class declares ``capability`` in ``_capabilities``.

    A subclass does not inherit a declaration (it may change what it promises): it declares
    the capability again, as it declares its compiled steps (:class:`KernelSpec`).
    """
    return capability in type(component).__dict__.get("_capabilities", ())

_JSON_SCALARS = (str, bool, int, float, type(None))


class KernelSpec(NamedTuple):
    """How a component runs inside the filter's compiled loop (:mod:`novelty._kernels`).

    A component class that sets ``_kernel = KernelSpec(...)`` in its own body
    (a subclass does not inherit it: it may change the arithmetic) provides
    numba-compilable step functions in the module ``steps``, and says how its
    state and parameters reach them:

    ``params``
        the parameters the steps read, by name, from their record ``p``: one
        field per parameter, named and typed by the parameter's rule
        (``p.learning_rate``; ``p.has_radius`` when it may be None; an option
        string as an int64 whose values the step module names with
        :func:`novelty.rules.option_code`): the table is in
        :mod:`novelty._kernels.params`. A nested component (see ``nested``)
        is a field holding its own record. A synapse's record also holds the
        schedule's parameters, which its base class declares
        (``_kernel_base_params``).
    ``arrays``
        per-unit state arrays, in the order of the tuple the steps receive
        (a dotted name reaches into a nested component).
    ``square``
        those of ``arrays`` that are unit x unit (grown in both dimensions).
    ``counters``
        integer attributes the steps read and update (an int64 vector).
    ``ignores``
        parameters that do not change what is learned (initialisation):
        every parameter is in ``params`` or here (a test checks it).
    ``nested``
        ``(attribute, steps)`` pairs: a nested component (named in
        ``params``) that the steps drive with the step functions of module
        ``steps``, so it must declare those (else the reference runs).
    ``fitted``
        ``(name, type)`` pairs for the names in ``params`` that are values
        fitted from the data, not parameters (no rule gives their type):
        ``float``, ``int`` or ``bool``.

    A synapse's ``steps`` module defines only its equation, ``advance`` and
    ``fresh`` (the schedule of who is stimulated and when is the driver's, with
    the base class's parameters); a clusterer's ``match``, ``room`` and
    ``adapt`` (signatures in :mod:`novelty._kernels.drivers` and in the guide,
    docs/guide/engine.md).
    """

    steps: str
    params: tuple = ()
    arrays: tuple = ()
    square: tuple = ()
    counters: tuple = ()
    ignores: tuple = ()
    nested: tuple = ()
    fitted: tuple = ()


class StateError(ValueError):
    """Learned state that is missing, inconsistent or of the wrong type."""


def _is_state_name(name: str) -> bool:
    return name.endswith("_") and not name.startswith("_") and name.isidentifier()


class Component(BaseEstimator):
    """Base of clusterers, synapses and detectors.

    Subclasses declare ``_parameter_rules`` (see :mod:`novelty._validation`)
    and may override :meth:`_check_state` (called after a model file is read)
    and :meth:`_rebuild_scratch` (recomputes private caches from the state).
    """

    _parameter_rules: dict = {}
    #: the kind of component (``"detector"``, ``"clusterer"``, ``"synapse"``): the registry
    #: that names it in a model file (:func:`novelty.registry.of_kind`); set by the three bases
    _kind: str | None = None
    #: parameters that a base class's compiled code reads from the record of every subclass
    #: that declares steps (:class:`KernelSpec`), before the subclass's own: a synapse's schedule
    _kernel_base_params: tuple = ()
    #: how many times an attribute was set on this object (see :meth:`__setattr__`)
    _changes = 0

    def __setattr__(self, name: str, value: Any) -> None:
        """Set an attribute and count the change: a compiled engine holding this component's
        state and parameters (:mod:`novelty._kernels.engine`), and a filter holding it as a part,
        compare one count instead of every value to know whether anything was replaced or set
        since they last read it. The engine writes the counters it owns back without counting
        (through ``vars``).

        A fitted part, one an engine holds (:func:`held_by_engine`), is read-only from outside
        the engine's own writes (:func:`engine_writes`): setting a public attribute (a parameter
        or learned state) on it raises :class:`FittedPartError`, which says what to do instead,
        and its learned arrays are read-only. The engine is the one writer of what a detector
        learned."""
        if vars(self).get("_held") and not vars(self).get("_writing") and not name.startswith("_"):
            raise _fitted_write_error(self, name)
        object.__setattr__(self, name, value)
        vars(self)["_changes"] = self._changes + 1

    def __delattr__(self, name: str) -> None:
        if vars(self).get("_held") and not vars(self).get("_writing") and not name.startswith("_"):
            raise _fitted_write_error(self, name)
        object.__delattr__(self, name)
        vars(self)["_changes"] = self._changes + 1

    def _validate_params(self) -> None:
        validate_parameters(self)

    # ------------------------------------------------------------ fitted state
    def _state_names(self) -> list[str]:
        return sorted(name for name in vars(self) if _is_state_name(name))

    def _export_state(self) -> tuple[dict[str, np.ndarray], dict[str, Any], dict[str, "Component"]]:
        """Split learned state into arrays, JSON values and nested components."""
        arrays: dict[str, np.ndarray] = {}
        values: dict[str, Any] = {}
        children: dict[str, Component] = {}
        for name in self._state_names():
            value = getattr(self, name)
            if isinstance(value, Component):
                children[name] = value
            elif isinstance(value, np.ndarray) and value.dtype != object:
                arrays[name] = value
            elif isinstance(value, np.ndarray):  # e.g. feature_names_in_ (strings)
                values[name] = {"__strings__": [str(v) for v in value.tolist()]}
            elif isinstance(value, np.generic):
                values[name] = value.item()
            elif _is_json_value(value):
                values[name] = list(value) if isinstance(value, tuple) else value
            else:
                raise StateError(
                    f"{type(self).__name__}.{name} is a {type(value).__name__}, which a model "
                    "file cannot hold (arrays, numbers, strings and components only)."
                )
        return arrays, values, children

    def _import_state(
        self,
        arrays: dict[str, np.ndarray],
        values: dict[str, Any],
        children: dict[str, "Component"],
    ) -> None:
        """Set learned state read from a file, then check it is consistent."""
        for name in list(arrays) + list(values) + list(children):
            if not _is_state_name(name):
                raise StateError(f"'{name}' is not a learned-state attribute name.")
        for name, value in values.items():
            if isinstance(value, dict) and set(value) == {"__strings__"} and _is_json_value(value["__strings__"]):
                value = np.asarray(value["__strings__"], dtype=object)
            elif not _is_json_value(value):
                # only what _export_state writes: a value it could not write back is not a model's
                raise StateError(f"{type(self).__name__}.{name} is {value!r}; a model file holds a number, a "
                                 "string or a flat list of them there.")
            setattr(self, name, value)
        for name, value in arrays.items():
            setattr(self, name, np.array(value))  # own, writable copy
        for name, value in children.items():
            setattr(self, name, value)
        self._check_state()
        self._rebuild_scratch()

    def _check_state(self) -> None:
        """Raise :class:`StateError` if the learned state is inconsistent."""

    def _rebuild_scratch(self) -> None:
        """Recompute private caches (names starting with ``_``) from the state."""


class FittedPartError(AttributeError):
    """An attribute set on a fitted part (a filter's or a map's ``clusterer_`` or ``synapse_``)
    from outside its engine, the one writer of what the detector learned
    (:meth:`Component.__setattr__`)."""


def held_by_engine(component) -> None:
    """Mark ``component`` as a fitted part an engine holds: an attribute set on it from outside
    the engine's writes raises (:meth:`Component.__setattr__`), and its learned arrays are
    read-only (:func:`engine_writes` makes them writable while the engine writes). Kept in its
    ``__dict__`` (a copy of a filter copies it; a model file, which holds learned state only,
    does not)."""
    vars(component)["_held"] = True
    if not vars(component).get("_writing"):
        _lock(component)


class engine_writes:
    """The block in which an engine (or the checks it relies on) writes its fitted ``parts``:
    their attributes may be set, and the learned arrays they were locked with are writable;
    on leaving, every learned array of a held part is read-only again. Re-entrant. A class,
    not a generator: the reference engine enters one at every call."""

    __slots__ = ("parts", "before")

    def __init__(self, parts):
        self.parts = parts

    def __enter__(self) -> None:
        self.before = before = []
        for part in self.parts:
            d = vars(part)
            was = d.get("_writing", False)
            before.append(was)
            if not was:
                _unlock(part)
            d["_writing"] = True

    def __exit__(self, *exc) -> bool:
        for part, was in zip(self.parts, self.before):
            d = vars(part)
            d["_writing"] = was
            if not was and d.get("_held"):
                _lock(part)
        return False


def _lock(component) -> None:
    """Make the part's learned arrays (plain ndarrays) read-only, remembering those it made so in
    ``_locked``: ``(count, {name: array})``, the part's count of changes then and the arrays (a
    deep copy of the part copies them with its attributes). An array that was read-only already (a
    memory map's, a caller's) is not the part's to unlock. While no attribute was set since (the
    count), the arrays are the same ones: they are locked again without a look at the others."""
    d = vars(component)
    changes = d.get("_changes", 0)
    at, locked = d.get("_locked", (None, {}))
    if at == changes:
        for value in locked.values():
            value.setflags(write=False)
        return
    locked = {name: value for name, value in locked.items() if d.get(name) is value}
    for name, value in d.items():
        if type(value) is np.ndarray and name[-1] == "_" and name[0] != "_":
            if value.flags.writeable:
                value.setflags(write=False)
                locked[name] = value
            elif locked.get(name) is not value:
                locked.pop(name, None)
    d["_locked"] = (changes, locked)


def _unlock(component) -> None:
    """Make writable again the arrays :func:`_lock` made read-only that the part still holds (a view
    only once its base is: those that fail are tried again after the others)."""
    d = vars(component)
    at, locked = d.get("_locked", (None, None))
    if not locked:
        return
    same = at == d.get("_changes", 0)  # else an attribute was set since: only those it still holds
    later = []
    for name, value in locked.items():
        if same or d.get(name) is value:
            try:
                value.setflags(write=True)
            except ValueError:  # a view of another of its arrays, not writable yet
                later.append(value)
    for value in later:
        try:
            value.setflags(write=True)
        except ValueError:  # a view of memory locked elsewhere: the reference engine copies it (adopt)
            pass


def _fitted_write_error(component, name: str) -> FittedPartError:
    kind = component._kind or "part"
    if name in component._get_param_names():
        instead = (f"to learn with another value, set it on the detector (set_params({kind}__{name}=...)) "
                   "and fit again")
    else:
        instead = "to start from another learned state, fit again (or load a model file)"
    return FittedPartError(f"{type(component).__name__}.{name} cannot be set on a fitted part (a detector's "
                           f"{kind}_): the detector's engine is the one writer of what it learned; "
                           f"{instead}.")


def _is_json_value(value) -> bool:
    """Whether a model file's JSON holds ``value`` as it is: a scalar, or a flat list (tuple) of them."""
    return isinstance(value, _JSON_SCALARS) or (
        isinstance(value, (list, tuple)) and all(isinstance(v, _JSON_SCALARS) for v in value))


#: the largest count a model file may hold (steps, unit ids): exact in float64, and more than
#: 28 years of scans at ten million a second
MAX_COUNT = 2**53
_INT64 = np.iinfo(np.int64)


def check_array_state(owner: Component, name: str, ndim: int, dtype_kind: str = "f",
                      shape: tuple | None = None) -> np.ndarray:
    """Check one state array read from a file: presence, rank, type, shape, finiteness.

    Real arrays must be float64 (what learning computes in; a float16 copy
    would change every result) and finite; integer arrays must fit int64.
    """
    value = getattr(owner, name, None)
    where = f"{type(owner).__name__}.{name}"
    if not isinstance(value, np.ndarray):
        raise StateError(f"{type(owner).__name__} state is missing the array '{name}'.")
    if value.ndim != ndim or value.dtype.kind not in dtype_kind:
        raise StateError(f"{where} must be a {ndim}-D array of kind {dtype_kind!r}; "
                         f"got {value.ndim}-D {value.dtype}.")
    if value.dtype.kind == "f" and value.dtype != np.float64:
        raise StateError(f"{where} must be a float64 array; got {value.dtype}.")
    if shape is not None and any(s is not None and s != v for s, v in zip(shape, value.shape)):
        raise StateError(f"{where} has shape {value.shape}; expected {shape}.")
    if value.dtype.kind == "f" and not np.all(np.isfinite(value)):
        raise StateError(f"{where} contains NaN or infinity.")
    if value.dtype.kind in "iu" and value.size and (value.dtype.itemsize > 8 or (
            value.dtype.kind == "u" and value.dtype.itemsize == 8 and value.max() > _INT64.max)):
        raise StateError(f"{where} must hold integers within int64.")
    return value


def check_int_state(owner: Component, name: str, low: int = 0, high: int = MAX_COUNT) -> int:
    """Check one integer of the state read from a file: an int in ``[low, high]``."""
    value = getattr(owner, name, None)
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not low <= value <= high:
        bound = "2**53" if high == MAX_COUNT else str(high)
        raise StateError(f"{type(owner).__name__}.{name} must be an int in [{low}, {bound}]; "
                         f"got {value!r}.")
    return int(value)
