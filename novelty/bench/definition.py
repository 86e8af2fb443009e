"""What a cell computes as it resolves now: a digest of its built detector and of its task's data.

A cell's id (:attr:`~novelty.bench.specs.Cell.id`) hashes the suite as
written: a preset's name and the options given. What the name resolves to
can change between releases (a preset's parameters, its clusterer; a task
generator's placement of objects), and then rows computed by the old
definition must not be reused. Each row therefore records
:func:`definition_digest`, and a resumed run recomputes a finished cell
whose digest differs from the one it would get now
(:func:`novelty.bench.runner.run_bench`). Each row also records the task
half alone (:func:`task_digest`): seeds whose rows share it ran on one world
(a recording), seeds whose rows differ on worlds built independently, which
is what a comparison over seeds needs to know (:mod:`novelty.bench.compare`).

The digest covers:

- the detector as :func:`~novelty.bench.build.make_detector` builds it for
  the cell: its class and every parameter (``get_params(deep=False)``, nested
  components the same way, seed included), read by :func:`describe`;
- the task's data as :func:`~novelty.bench.build.load_task` loads it for the
  cell: every array of the :class:`~novelty.data.Dataset` and its metadata,
  less where the data was read from (``source``, ``sources``: the same scans
  read from another folder are the same task).

Classes are known by name, not by their code: a change inside a
component's methods (not its parameters) is not seen here. Each row names
the revision that computed it (``git_revision``); after such a change, run
the suite from scratch.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import math
import re
import types
from typing import Any, Mapping

import numpy as np

from ..data import Dataset
from .build import load_task, make_detector
from .specs import Cell

__all__ = ["definition_digest", "task_digest", "describe", "DEFINITION_COLUMN", "TASK_DATA_COLUMN"]

#: the column of a results row that holds :func:`definition_digest`
DEFINITION_COLUMN = "definition"
#: the column of a results row that holds :func:`task_digest` (seeds of one world share it)
TASK_DATA_COLUMN = "task_data"
#: metadata naming where a dataset was read from, not what it holds
_LOCATION_KEYS = ("source", "sources")
#: an object's default repr names its address, which differs from process to process
_ADDRESS = re.compile(r" at 0x[0-9a-fA-F]+")
_MAX_DEPTH = 64


def definition_digest(cell: Cell, task: str | None = None) -> str:
    """A short hash of the cell's detector and task data as they resolve now (see the module's text).

    ``task``: the cell's :func:`task_digest`, when known already.
    """
    task = task_digest(cell) if task is None else task
    return _digest({"detector": describe(make_detector(cell)), "task": task})


def task_digest(cell: Cell) -> str:
    """A short hash of the cell's task data (less where it was read from): equal for two seeds of one world."""
    return _digest(describe(_without_location(load_task(cell))))


def _digest(what: Any) -> str:
    text = json.dumps(what, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _without_location(data):
    if isinstance(data, Dataset) and any(key in data.metadata for key in _LOCATION_KEYS):
        metadata = {k: v for k, v in data.metadata.items() if k not in _LOCATION_KEYS}
        return dataclasses.replace(data, metadata=metadata)
    return data


def describe(value: Any, depth: int = 0) -> Any:
    """``value`` as plain JSON data that is equal exactly when what it defines is.

    Numbers and text as they are (a non-finite float as its name); arrays by
    dtype, shape and a hash of their bytes; containers item by item (a set
    sorted); an estimator or component by its class and
    ``get_params(deep=False)``; a dataclass (a Dataset) by its class and
    fields; a numpy random generator by its state; a class or function by
    its module and qualified name (a function also by a hash of its code and
    the values it closes over, so that two lambdas differ; a bound method
    also by its object); any other object, a callable one included, by its
    class and attributes.
    """
    if depth > _MAX_DEPTH:
        raise ValueError("a parameter nested too deeply to describe (a cycle?)")
    inner = depth + 1
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, np.generic):
        return describe(value.item(), inner)
    if isinstance(value, np.ndarray):
        return _describe_array(value, inner)
    if isinstance(value, (list, tuple)):
        return [describe(v, inner) for v in value]
    if isinstance(value, (set, frozenset)):
        return {"set": sorted((describe(v, inner) for v in value), key=_canonical)}
    if isinstance(value, Mapping):
        return {"mapping": sorted(([describe(k, inner), describe(v, inner)] for k, v in value.items()),
                                  key=_canonical)}
    if isinstance(value, np.random.Generator):
        return {"generator": describe(value.bit_generator.state, inner)}
    if isinstance(value, np.random.RandomState):
        return {"random_state": describe(value.get_state(), inner)}
    if _named_callable(value):
        return _describe_callable(value, inner)
    kind = f"{type(value).__module__}.{type(value).__qualname__}"
    if hasattr(value, "get_params"):
        return {"class": kind, "params": describe(value.get_params(deep=False), inner)}
    if dataclasses.is_dataclass(value):
        return {"class": kind, "fields": describe({f.name: getattr(value, f.name)
                                                   for f in dataclasses.fields(value)}, inner)}
    if hasattr(value, "__dict__"):
        return {"class": kind, "attributes": describe(vars(value), inner)}
    return {"class": kind, "repr": _ADDRESS.sub("", repr(value))}


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"))


def _describe_array(value: np.ndarray, depth: int) -> Any:
    if value.dtype.hasobject:
        return {"array": "object", "shape": list(value.shape), "items": describe(value.ravel().tolist(), depth)}
    data = np.ascontiguousarray(value)
    return {"array": data.dtype.str, "shape": list(data.shape), "sha256": hashlib.sha256(data.tobytes()).hexdigest()}


def _named_callable(value: Any) -> bool:
    """A class, function, method, partial or other callable with a name of its own (a ufunc);
    a callable instance of a class (its state in its attributes) is read as an object."""
    if isinstance(value, (type, functools.partial, types.MethodType)):
        return True
    return callable(value) and not hasattr(value, "get_params") and hasattr(value, "__qualname__")


def _describe_callable(value: Any, depth: int) -> Any:
    if isinstance(value, functools.partial):
        return {"partial": describe(value.func, depth), "args": describe(value.args, depth),
                "keywords": describe(value.keywords, depth)}
    if isinstance(value, types.MethodType):  # a bound method: its object's state too
        return {"method": describe(value.__func__, depth), "of": describe(value.__self__, depth)}
    name = f"{getattr(value, '__module__', '')}.{value.__qualname__}"
    if isinstance(value, types.FunctionType):
        # a lambda or a local function is not known by its name alone: its code and what it holds
        cells = [cell.cell_contents for cell in value.__closure__ or ()]
        return {"function": name, "code": _code_digest(value.__code__),
                "defaults": describe([value.__defaults__, value.__kwdefaults__, cells], depth)}
    return {"callable": name}


def _code_digest(code: types.CodeType) -> str:
    """A hash of a code object's instructions, constants (nested code the same way) and names."""
    digest = hashlib.sha256(code.co_code)
    for const in code.co_consts:
        digest.update(_code_digest(const).encode() if isinstance(const, types.CodeType) else repr(const).encode())
    digest.update(repr(code.co_names).encode())
    return digest.hexdigest()[:16]
