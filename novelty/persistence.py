"""Model files: numpy arrays in an ``.npz`` archive plus JSON metadata. Never pickle.

A file holds one entry ``meta`` (UTF-8 JSON, stored as a uint8 array) and one
array per learned array attribute, named by its path (``root/clusterer_/weights_``).
The metadata names every component by its *registry name* and gives its
parameters and scalar state::

    {"format": "novelty-model", "format_version": 1, "novelty_version": "...",
     "root": {"kind": "detector", "name": "habituating",
              "params": {...}, "values": {...}, "arrays": ["n_features_in_", ...],
              "children": {"clusterer_": {...}, "synapse_": {...}}}}

Reading uses ``numpy.load(allow_pickle=False)`` and builds classes only from
the registries, so a crafted file can neither unpickle objects nor import
arbitrary modules: it can only name components that are already registered.
Whatever is wrong with a file (not a zip, truncated, newer format, unknown
names, inconsistent shapes, impossible state) raises :class:`ModelFileError`
and runs nothing; no other exception escapes :func:`load` for what a file
holds.

Reading is bounded before anything is read: members must be stored
uncompressed, as :func:`save` writes them (a compressed member could inflate
without limit: a zip bomb); each array's declared shape must account for
exactly the bytes its member holds, so no allocation exceeds the file;
the metadata is at most :data:`MAX_META_BYTES`; and no more bytes are read
in all than the file holds (members that overlap are refused). :func:`save`
reads the file back with the same checks before moving it into place, so no
file is ever written that :func:`load` refuses.

The format is one module although it is a little over 300 lines: writing
and reading are each other's inverse, and :func:`save` runs every check of
:func:`load`, so the two are read together.
"""

from __future__ import annotations

import json
import math
import os
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from ._atomic import not_regular, write_atomically
from ._version import __version__
from ._component import Component, StateError
from .registry import UnknownNameError, of_kind

__all__ = ["save", "load", "ModelFileError", "FORMAT", "FORMAT_VERSION", "MAX_META_BYTES"]

FORMAT = "novelty-model"
FORMAT_VERSION = 1
_KINDS = ("detector", "clusterer", "synapse")
#: the largest metadata entry read (a model's is a few kB; feature names can add more)
MAX_META_BYTES = 64 * 2**20


class ModelFileError(ValueError):
    """A file that is not a readable novelty model."""


def _kind_of(component: Component) -> str:
    if isinstance(component, Component) and component._kind in _KINDS:
        return component._kind
    raise StateError(f"{type(component).__name__} is not a detector, clusterer or synapse.")


def _name_of(component: Component) -> tuple[str, str]:
    kind = _kind_of(component)
    name = of_kind(kind).name_of(component)
    if name is None:
        raise StateError(
            f"{type(component).__name__} is not registered as a {kind}, so a model file "
            f"cannot name it. Register it (novelty.register_{kind}) before saving."
        )
    return kind, name


# ------------------------------------------------------------------- writing
def _encode_value(value: Any) -> Any:
    if isinstance(value, Component):
        kind, name = _name_of(value)
        return {"__component__": {"kind": kind, "name": name,
                                  "params": _encode_params(value.get_params(deep=False))}}
    if isinstance(value, tuple):
        return {"__tuple__": [_encode_value(v) for v in value]}
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        return {"__dict__": {k: _encode_value(v) for k, v in value.items()}}
    if isinstance(value, list):
        return [_encode_value(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (str, bool, int, float, type(None))):
        return value
    raise StateError(
        f"A parameter of type {type(value).__name__} cannot be written to a model file "
        "(use numbers, strings, tuples, dicts with string keys, or registered components; "
        "an int seed for random_state)."
    )


def _encode_params(params: dict) -> dict:
    return {name: _encode_value(value) for name, value in params.items()}


def _encode(component: Component, prefix: str, arrays_out: dict) -> dict:
    kind, name = _name_of(component)
    arrays, values, children = component._export_state()
    for attr, arr in arrays.items():
        arrays_out[f"{prefix}/{attr}"] = arr
    return {
        "kind": kind,
        "name": name,
        "params": _encode_params(component.get_params(deep=False)),
        "values": {k: _encode_value(v) if not isinstance(v, dict) else v for k, v in values.items()},
        "arrays": sorted(arrays),
        "children": {attr: _encode(child, f"{prefix}/{attr}", arrays_out) for attr, child in children.items()},
    }


def save(detector: Component, path: str | os.PathLike) -> None:
    """Write ``detector`` to ``path``: whole, and only if :func:`load` will read it back.

    The file is written under a temporary name beside ``path``, read back
    with every check of :func:`load`, then moved into place; a state that
    would not load (NaN weights, an impossible efficacy) raises
    :class:`StateError` and leaves ``path`` as it was.
    """
    if not hasattr(detector, "n_features_in_"):
        raise StateError(f"This {type(detector).__name__} is not fitted; there is nothing to save.")
    arrays: dict[str, np.ndarray] = {}
    root = _encode(detector, "root", arrays)
    meta = {"format": FORMAT, "format_version": FORMAT_VERSION, "novelty_version": __version__, "root": root}
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)

    def check(tmp: Path) -> None:
        try:
            _read(tmp, "the model")
        except ModelFileError as exc:
            raise StateError(f"Not saved to {path}: {exc}") from None

    write_atomically(path, lambda fh: np.savez(fh, **arrays), check=check)


# ------------------------------------------------------------------- reading
def _decode_value(value: Any) -> Any:
    if isinstance(value, dict):
        if set(value) == {"__component__"}:
            spec = value["__component__"]
            cls = _class_for(spec.get("kind"), spec.get("name"))
            return _construct(cls, spec.get("params", {}))
        if set(value) == {"__tuple__"}:
            return tuple(_decode_value(v) for v in value["__tuple__"])
        if set(value) == {"__dict__"} and isinstance(value["__dict__"], dict):
            return {k: _decode_value(v) for k, v in value["__dict__"].items()}
        if set(value) == {"__strings__"}:
            return value
        raise ModelFileError(f"Unexpected object in model metadata: keys {sorted(value)}.")
    if isinstance(value, list):
        return [_decode_value(v) for v in value]
    return value


def _class_for(kind: Any, name: Any) -> type:
    if kind not in _KINDS or not isinstance(name, str):
        raise ModelFileError(f"Model file names an invalid component ({kind!r}, {name!r}).")
    try:
        cls = of_kind(kind).get(name)
    except UnknownNameError as exc:
        raise ModelFileError(f"Model file needs the {kind} {name!r}, which is not registered: {exc}") from None
    if not (isinstance(cls, type) and issubclass(cls, Component)):
        raise ModelFileError(f"Model file names {kind} {name!r}, which is not a component class.")
    return cls


def _construct(cls: type, params: Any) -> Component:
    if not isinstance(params, dict):
        raise ModelFileError(f"Parameters of {cls.__name__} in the model file are not a mapping.")
    valid = cls._get_param_names()
    unknown = sorted(set(params) - set(valid))
    if unknown:
        raise ModelFileError(f"Model file gives {cls.__name__} unknown parameters {unknown}.")
    decoded = {k: _decode_value(v) for k, v in params.items()}
    for name, value in decoded.items():
        # a count no run reaches, which the compiled steps could not hold either
        if isinstance(value, int) and not isinstance(value, bool) and not -2**63 <= value < 2**63:
            raise ModelFileError(f"Model file gives {cls.__name__}.{name} = {value}, beyond the 64-bit "
                                 "integers a parameter holds.")
    obj = cls(**decoded)
    try:
        obj._validate_params()
    except ValueError as exc:
        raise ModelFileError(f"Model file has invalid parameters: {exc}") from None
    return obj


def _decode(spec: Any, prefix: str, npz) -> Component:
    if not isinstance(spec, dict):
        raise ModelFileError("Model metadata is malformed (a component is not an object).")
    obj = _construct(_class_for(spec.get("kind"), spec.get("name")), spec.get("params", {}))
    values = spec.get("values", {})
    names = spec.get("arrays", [])
    children = spec.get("children", {})
    if not (isinstance(values, dict) and isinstance(names, list) and isinstance(children, dict)):
        raise ModelFileError("Model metadata is malformed (state lists).")
    arrays = {}
    for attr in names:
        key = f"{prefix}/{attr}"
        if not isinstance(attr, str) or key not in npz.files:
            raise ModelFileError(f"Model file lacks the array {key!r}.")
        arrays[attr] = npz[key]
    decoded_children = {attr: _decode(child, f"{prefix}/{attr}", npz) for attr, child in children.items()}
    obj._import_state(arrays, {k: _decode_value(v) for k, v in values.items()}, decoded_children)
    return obj


class _Archive:
    """The members of a model file, each read only after its size and shape are checked."""

    def __init__(self, zf: zipfile.ZipFile, budget: int, name: str):
        self.zf, self.budget, self.name = zf, budget, name
        self.members = {info.filename: info for info in zf.infolist()}
        self.files = [n[:-4] for n in self.members if n.endswith(".npy")]

    def __contains__(self, key: str) -> bool:
        return f"{key}.npy" in self.members

    def __getitem__(self, key: str) -> np.ndarray:
        info = self.members[f"{key}.npy"]
        if info.compress_type != zipfile.ZIP_STORED:
            raise ModelFileError(f"{self.name}: the entry {key!r} is compressed; model files store "
                                 "their arrays uncompressed (a compressed entry could inflate without bound).")
        self.budget -= info.file_size
        if self.budget < 0:
            raise ModelFileError(f"{self.name}: its entries claim more bytes than the file holds "
                                 "(entries overlap).")
        if key == "meta" and info.file_size > MAX_META_BYTES:
            raise ModelFileError(f"{self.name}: the metadata entry has {info.file_size} bytes; "
                                 f"at most {MAX_META_BYTES} are read.")
        with self.zf.open(info) as fh:
            version = np.lib.format.read_magic(fh)
            if version not in ((1, 0), (2, 0)):
                raise ModelFileError(f"{self.name}: the entry {key!r} has npy format {version}.")
            read_header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                           else np.lib.format.read_array_header_2_0)
            shape, fortran, dtype = read_header(fh)
            if dtype.hasobject or dtype.kind not in "biuf" or dtype.fields is not None:
                raise ModelFileError(f"{self.name}: the entry {key!r} holds {dtype} values; "
                                     "model files hold plain numbers.")
            size = info.file_size - fh.tell()
            declared = math.prod(shape) * dtype.itemsize
            if declared != size:
                raise ModelFileError(f"{self.name}: the entry {key!r} declares shape {shape} of "
                                     f"{dtype} ({declared} bytes) but holds {size} bytes.")
            data = fh.read(size)  # the archive's CRC is checked at the end
        array = np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran else "C")
        return array.astype(dtype.newbyteorder("="), copy=False)


def _read_meta(npz: _Archive, name: str) -> dict:
    if "meta" not in npz:
        raise ModelFileError(f"{name} has no 'meta' entry; it is not a novelty model file.")
    raw = npz["meta"]
    if raw.dtype != np.uint8 or raw.ndim != 1:
        raise ModelFileError(f"{name}: the 'meta' entry is not JSON text.")
    meta = json.loads(raw.tobytes().decode("utf-8"))
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        found = meta.get("format") if isinstance(meta, dict) else None
        raise ModelFileError(f"{name} is not a novelty model file (format {found!r}).")
    version = meta.get("format_version")
    if not isinstance(version, int) or version < 1:
        raise ModelFileError(f"{name} has an invalid format version {version!r}.")
    if version > FORMAT_VERSION:
        raise ModelFileError(
            f"{name} was written in model format {version} (novelty "
            f"{meta.get('novelty_version')}); this version reads format {FORMAT_VERSION} "
            "or older. Upgrade novelty to read it."
        )
    return meta


def _read(path: str | os.PathLike, name: str) -> Component:
    """:func:`load`, naming the file ``name`` in messages."""
    kind = not_regular(path)
    if kind is not None:  # a FIFO would block the open, a device never end
        raise ModelFileError(f"{name} is {kind}, not a regular file; a model file is read only from a file.")
    with open(path, "rb") as fh:  # FileNotFoundError and the like propagate as they are
        magic = fh.read(4)
        if magic == b"\x93NUM":
            raise ModelFileError(f"{name} is a single numpy array, not a novelty model file.")
        if magic != b"PK\x03\x04":
            # np.load would call anything else "pickled data" and suggest allow_pickle
            raise ModelFileError(f"{name} is not a novelty model file (not an .npz archive).")
        try:
            fh.seek(0)
            with zipfile.ZipFile(fh) as zf:
                npz = _Archive(zf, os.fstat(fh.fileno()).st_size, name)
                return _decode(_read_meta(npz, name).get("root"), "root", npz)
        except ModelFileError:
            raise
        except RecursionError:
            raise ModelFileError(f"{name}: its metadata is nested too deeply.") from None
        except Exception as exc:  # noqa: BLE001 - whatever a damaged file provokes is the file's fault
            detail = str(exc) if isinstance(exc, StateError) else f"{type(exc).__name__}: {exc}"
            raise ModelFileError(f"{name} is not a valid novelty model file: {detail}") from None


def load(path: str | os.PathLike) -> Component:
    """Read a detector written by :func:`save` (or ``detector.save``).

    Raises
    ------
    ModelFileError
        For anything wrong with what the file holds (and nothing else does).
    OSError
        When the file cannot be opened (``FileNotFoundError``, ...).
    """
    return _read(path, str(path))
