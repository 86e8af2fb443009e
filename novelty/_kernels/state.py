"""What an engine reads, checked in one place before any engine works on it.

An engine (:mod:`novelty._kernels.interface`) reads a fitted filter's parts: the
clusterer's weights, the per-unit arrays and counters the parts declare
(:class:`~novelty._component.KernelSpec`), those of their nested components,
the synapse bank's arrays, and the parts' parameters. The compiled engine's
loops trust all of it: weights wider than the scans, fewer units than a map's
grid or a counter beyond int64 would make them read or write past an array.
So every engine, compiled or reference, works only on a state that passed
:func:`check_state`, and gives the same :class:`~novelty._component.StateError`
for the same damaged state:

- :func:`check_state`: everything, whenever something was set on a part since
  the engine last read it (a fit, a load, ``set_params``, an attribute set
  directly: each counts a change, :meth:`novelty._component.Component.__setattr__`).
  Shapes first, against ``n_features_in_`` and each other, before any pass over
  the values (weights of shape (100, 10**7) are refused at once, not scanned);
  then types, counters within ``[0, 2**53]``, the parts' parameters against
  their rules, the units against the clusterer's parameters (a map's grid:
  ``Clusterer._check_units``), each component's own checks (``_check_state``:
  what a model file is held to, such as unique unit ids, counts of at least
  one, a symmetric graph) and finiteness (NaN would make the compiled winner
  search and numpy's ``argmin`` part ways; a count of 0 would make NaN). Not
  the efficacy's range under the filter's stimulus, which a model file is
  also held to: a parameter set on a fitted part (Stanley's ``alpha``, say)
  is used as it is, with efficacies learned under another;
- :func:`check_finite`: before every batch call, what writing into an array in
  place can change, its values (its shape, type and layout stay the engine's).

Layout is not refused: an engine takes a strided, Fortran-ordered or read-only
array as it is and makes its own writable copy where it writes
(:meth:`~novelty._kernels.interface.Engine.adopt`); a memory-mapped array
(``np.memmap``, as joblib loads a model) is taken as the plain array of the
same memory first.
"""

from __future__ import annotations

import numbers

import numpy as np

from .._component import MAX_COUNT, Component, StateError, check_int_state, engine_writes
from .._validation.scans import MAX_SCAN_NORM
from .params import attribute, spec_of

__all__ = ["check_state", "check_layout", "check_finite", "check_efficacies", "parts_of", "per_unit_arrays"]


def parts_of(clusterer, synapse) -> tuple:
    """The components an engine reads: the pair and every component nested in either
    (a state attribute holding a component, such as a growing network's firing counters)."""
    out: list = []
    for part in (clusterer, synapse):
        out.append(part)
        out.extend(value for name, value in vars(part).items()
                   if name.endswith("_") and not name.startswith("_") and isinstance(value, Component))
    return tuple(out)


def per_unit_arrays(component) -> dict[str, bool]:
    """The names of the component's per-unit arrays, each with whether it is unit x unit:
    those its compiled steps declare (``KernelSpec.arrays``, ``square``) and a synapse's
    ``_per_unit`` (which every synapse grows and shrinks with its clusterer)."""
    names = {name: False for name in getattr(type(component), "_per_unit", ())}
    spec = spec_of(component)
    if spec is not None:
        names.update((name, name in spec.square) for name in spec.arrays)
    return names


def check_state(detector) -> None:
    """Raise :class:`StateError` unless the fitted parts of ``detector`` (a habituating filter)
    are what an engine may read (module docstring); the message names the attribute."""
    owner, clusterer, synapse, parts = check_layout(detector)
    for component in parts:
        try:
            component._validate_params()
        except ValueError as exc:  # a parameter set on a fitted part
            raise StateError(f"{_where(owner, component, clusterer, synapse)}: {exc}") from None
    for component in parts:
        component._check_state()
    check_finite((f"{_where(owner, component, clusterer, synapse)}.{name}", value)
                 for component in parts for name, value in vars(component).items()
                 if name.endswith("_") and type(value) is np.ndarray)


def check_layout(detector) -> tuple:
    """The part of :func:`check_state` that bounds what the compiled loops index: the parts'
    types, every declared array's type and shape against ``n_features_in_`` and the units,
    the counters within ``[0, 2**53]``, the units against a map's grid. Raises
    :class:`StateError`; returns ``(the owner's name, clusterer, synapse, parts)``.

    Alone, for a deep copy of a checked state (:class:`~.interface.CheckedCopy`), so that a
    copy torn by a thread learning while it was made (arrays copied before and after the
    network grew) is refused, not read past, at a fraction of the whole check's cost."""
    owner = type(detector).__name__
    n_features = check_int_state(detector, "n_features_in_", low=1)
    clusterer, synapse = _part(detector, "clusterer_", "clusterer"), _part(detector, "synapse_", "synapse")
    for component in parts_of(clusterer, synapse):
        _unmap(component)
    W = _array(clusterer, "weights_", f"{owner}.clusterer_")
    if W.ndim != 2 or W.shape[1] != n_features or W.shape[0] < 1:
        raise StateError(f"{owner}.clusterer_.weights_ has shape {W.shape}; the filter reads "
                         f"(n_units, {n_features}): at least one unit, n_features_in_ = {n_features} "
                         "features (the scans').")
    n = W.shape[0]
    parts = parts_of(clusterer, synapse)
    for component in parts:
        where = _where(owner, component, clusterer, synapse)
        for name, square in per_unit_arrays(component).items():
            a = _array(component, name, where)
            if a.dtype.kind not in "biuf":
                raise StateError(f"{where}.{name} holds {a.dtype} values; it holds numbers.")
            shape = (n, n) if square else (n,) + a.shape[1:]
            if a.shape != shape or (name in getattr(type(component), "_per_unit", ()) and a.ndim != 1):
                raise StateError(f"{where}.{name} has shape {a.shape}; with {n} units (the rows of "
                                 f"clusterer_.weights_) it has shape {shape if square else (n,)}.")
        spec = spec_of(component)
        for name in spec.counters if spec is not None else ():
            value = getattr(component, name, None)
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral) \
                    or not 0 <= value <= MAX_COUNT:
                raise StateError(f"{where}.{name} must be an int in [0, 2**53]; got {value!r}.")
    clusterer._check_units(n)
    return owner, clusterer, synapse, parts


def check_finite(arrays) -> None:
    """Raise :class:`StateError` if a float array of ``arrays`` (``(name, array)`` pairs) holds
    NaN or infinity: values written into an engine's state in place."""
    for name, a in arrays:
        if a.dtype.kind == "f" and not np.isfinite(a).all():
            raise StateError(f"{name} holds NaN or infinity, values that are not finite (written "
                             "into it in place?): the learned state is damaged. Refit, or set finite values.")


def check_efficacies(parts) -> None:
    """Raise :class:`StateError` if a synapse among ``parts`` (a nested one too, such as a growing
    network's firing counters) holds an efficacy beyond the scans' norm bound (``MAX_SCAN_NORM``),
    finite but written into it in place: an efficacy is a rate of learning and a novelty, near
    ``[0, 1]`` for every synapse here, and one as large as 1e300 would carry the weights past what
    a float holds within the call, where the compiled winner search and numpy's ``argmin`` part
    ways on what overflowed."""
    for part in parts:
        if part._kind != "synapse":
            continue
        efficacy = vars(part).get("efficacy_")
        if type(efficacy) is np.ndarray and efficacy.size and np.abs(efficacy).max() > MAX_SCAN_NORM:
            raise StateError(f"{type(part).__name__}.efficacy_ holds a value beyond {MAX_SCAN_NORM:g} in "
                             "magnitude (written into it in place?): an efficacy lies near [0, 1]; the "
                             "learned state is damaged. Refit, or set values within the bound.")


def _unmap(component) -> None:
    """Take a memory-mapped state array as the plain array of the same memory.

    ``np.memmap`` is what a model loaded by joblib with ``mmap_mode`` holds (scikit-learn's
    ``check_estimators_pickle`` loads one so): an ndarray over a file's bytes, read-only where the
    map is, with no behaviour of its own. Its plain view is taken as any read-only array is
    (module docstring); other subclasses of ndarray (a matrix, a masked array) change what
    indexing or arithmetic means, and are refused by the checks.
    """
    for name, value in list(vars(component).items()):
        if name.endswith("_") and type(value) is np.memmap:
            with engine_writes((component,)):
                setattr(component, name, value.view(np.ndarray))


def _part(detector, name: str, kind: str):
    value = getattr(detector, name, None)
    if not (isinstance(value, Component) and value._kind == kind):  # not isinstance(Clusterer):
        # this package must not import the components, whose step modules import it
        raise StateError(f"{type(detector).__name__}.{name} must be a {kind}; got {type(value).__name__}.")
    return value


def _array(component, name: str, where: str) -> np.ndarray:
    try:
        a = attribute(component, name)
    except AttributeError:
        raise StateError(f"{where} has no array '{name}'.") from None
    if type(a) is not np.ndarray:
        raise StateError(f"{where}.{name} must be a numpy array; got {type(a).__name__}.")
    if a.dtype.kind == "f" and a.dtype != np.float64:
        raise StateError(f"{where}.{name} must be a float64 array; got {a.dtype}.")
    return a


def _where(owner: str, component, clusterer, synapse) -> str:
    if component is clusterer:
        return f"{owner}.clusterer_"
    if component is synapse:
        return f"{owner}.synapse_"
    for part, label in ((clusterer, "clusterer_"), (synapse, "synapse_")):
        for name, value in vars(part).items():
            if value is component:
                return f"{owner}.{label}.{name}"
    return owner
