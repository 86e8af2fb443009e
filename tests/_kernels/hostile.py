"""Hostile states for the engines: the pairs, the mutations, and a child process that runs them.

A *case* is plain JSON, so that the same case runs in this process under the reference engine
(``NOVELTY_NO_KERNELS``) and in a child process under the compiled one, where a crash ends the
child and not the test run::

    {"pair": 3, "warm": true, "target": "clusterer_.weights_", "kind": "wider", "arg": 48,
     "seed": 7, "calls": ["stream", "novelty"]}

:func:`run_case` fits the pair (once per process), copies the fitted filter, optionally makes
its engine hold the state first (``warm``: one ``score_learn_one``, so that the engine, and the
single-scan protocol, have read the state before it is made hostile), applies the mutation to
the state array, counter or parameter named by ``target`` (:func:`mutate`), makes the calls,
and returns each call's outcome (the result's bytes, or the error's type and message) and a
digest of the state after them. Two engines that agree give equal outcomes.

Run as a script this module is the child: it reads one case per line on stdin and answers one
line of JSON per case on stdout (:func:`serve`).

The pairs (:func:`pairs`): every (clusterer, synapse) of the registries of which a part declares
compiled steps (:class:`novelty.KernelSpec`) or compiled scoring (``"nearest-unit"``), and the
guide's plugins (docs/guide/extending.md: the ``Fading`` synapse, compiled, and ``TinyKMeans``,
scored compiled; examples/novelty-plugin-example: the leader clusterer, the reference only).
"""

from __future__ import annotations

import atexit
import copy
import hashlib
import importlib
import json
import math
import re
import shutil
import sys
import tempfile
from functools import lru_cache
from pathlib import Path

import numpy as np

import novelty
from novelty._component import declares, engine_writes
from novelty._kernels.params import attribute, spec_of
from novelty._kernels.state import parts_of, per_unit_arrays
from novelty.registry import of_kind

ROOT = Path(__file__).resolve().parents[2]
EXTENDING = ROOT / "docs" / "guide" / "extending.md"
PLUGIN_SRC = ROOT / "examples" / "novelty-plugin-example" / "src"

#: the scans: a small corridor-like cloud, 6 features; fit on the first 40, the calls on the rest
N_FEATURES = 6
SCANS = np.random.default_rng(0).uniform(0.0, 1.0, (52, N_FEATURES))
FIT, CALL = SCANS[:40], SCANS[40:]
#: the calls a case may make after the mutation
CALLS = ("stream", "novelty", "score_one", "score_learn_one", "score_samples")


# ------------------------------------------------------------------------------ the pairs
def _compiled(cls) -> bool:
    try:
        instance = cls()
    except TypeError:  # a component that needs arguments: not one of the registries' built-ins
        return False
    if declares(instance, "several-winners"):  # a map's world cells: a map's loop, not the filter's pairs
        return False
    return spec_of(instance) is not None or declares(instance, "nearest-unit")


def pairs() -> list[tuple[str, str]]:
    """Every pair, as ``(clusterer, synapse)`` specs: registered names, or ``module:Class`` of
    the guide's plugins (written out by :func:`plugin_folder`, which the child imports too)."""
    clusterers = [n for n in of_kind("clusterer").names() if _compiled(of_kind("clusterer").get(n))]
    synapses = [n for n in of_kind("synapse").names() if _compiled(of_kind("synapse").get(n))]
    out = [(c, s) for c in clusterers for s in synapses]
    out += [("som", "fading:Fading"), ("gng", "fading:Fading"),
            ("tiny_kmeans:TinyKMeans", "stanley"), ("novelty_plugin_example:LeaderClusterer", "stanley")]
    return out


@lru_cache(maxsize=1)
def plugin_folder() -> str:
    """A folder holding the guide's plugins as modules: ``fading.py`` (the block the guide
    names so) and ``tiny_kmeans.py`` (the block of ``TinyKMeans``, without registering it by
    name, which would clash with a test that runs the guide's blocks)."""
    blocks = re.findall(r"```python\n(.*?)```", EXTENDING.read_text(encoding="utf-8"), flags=re.S)
    folder = Path(tempfile.mkdtemp(prefix="novelty-hostile-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)  # the child has ended by then
    fading = next(b for b in blocks if b.startswith("# fading.py\n"))
    tiny = next(b for b in blocks if "class TinyKMeans(" in b)
    tiny = "\n".join(line for line in tiny.splitlines()
                     if not line.startswith(("@novelty.register", "det = novelty.make")))
    (folder / "fading.py").write_text(fading, encoding="utf-8")
    (folder / "tiny_kmeans.py").write_text(tiny, encoding="utf-8")
    return str(folder)


def _importable(folder: str) -> None:
    for path in (folder, str(PLUGIN_SRC)):
        if path not in sys.path:
            sys.path.insert(0, path)


def _part(spec: str):
    if ":" not in spec:
        return spec
    module, name = spec.split(":")
    return getattr(importlib.import_module(module), name)()


_fitted: dict = {}


def fitted(pair: int, folder: str):
    """The pair's filter fitted on :data:`FIT` (once per process and engine kind), and, in the
    compiled process, with every kernel it may use compiled and an engine chosen."""
    key = (pair, novelty._kernels.environment.disabled())
    if key not in _fitted:
        _importable(folder)
        c, s = pairs()[pair]
        det = novelty.HabituatingFilter(clusterer=_part(c), synapse=_part(s)).fit(FIT)
        novelty._kernels.wait(det.clusterer_, det.synapse_)
        novelty._kernels.wait()
        det.novelty(CALL[:1])  # an engine chosen with every kernel ready
        _fitted[key] = det
    return _fitted[key]


# ------------------------------------------------------------------------ the targets
def targets(det) -> dict[str, str]:
    """What a case may make hostile in a fitted filter, each with its kind: ``"array"`` (the
    weights, every per-unit array the parts declare, every other array of their state),
    ``"count"`` (the counters the parts' steps declare, every int of their state, the filter's
    ``n_features_in_``) or ``"param"`` (a parameter of a fitted part, set by ``set_params``)."""
    c, s = det.clusterer_, det.synapse_
    out = {"n_features_in_": "count"}
    for part in parts_of(c, s):
        where = _path(det, part)
        declared = set(per_unit_arrays(part)) | {"weights_"} if part is c else set(per_unit_arrays(part))
        names = {n for n in declared if "." not in n}  # a nested part's arrays are the nested part's
        names |= {n for n, v in vars(part).items()
                  if n.endswith("_") and not n.startswith("_") and type(v) is np.ndarray}
        out.update((f"{where}.{n}", "array") for n in sorted(names) if hasattr(part, n))
        spec = spec_of(part)
        counts = set(spec.counters if spec is not None else ())
        counts |= {n for n, v in vars(part).items() if n.endswith("_") and not n.startswith("_")
                   and isinstance(v, (int, np.integer)) and not isinstance(v, bool)}
        out.update((f"{where}.{n}", "count") for n in sorted(counts))
        out.update((f"{where}.{n}", "param") for n in sorted(part.get_params(deep=False))
                   if not hasattr(part.get_params(deep=False)[n], "get_params"))
    return out


def _path(det, part) -> str:
    if part is det.clusterer_:
        return "clusterer_"
    if part is det.synapse_:
        return "synapse_"
    for label in ("clusterer_", "synapse_"):
        for name, value in vars(getattr(det, label)).items():
            if value is part:
                return f"{label}.{name}"
    raise AssertionError(part)


#: the mutations of an array: kind -> the arguments a case may give it
ARRAY_KINDS = {
    "wider": [1, 48, 100_000],        # more columns (a 1-D array becomes 2-D)
    "wide-zeros": [10_000_000],       # the crash: (units, 10**7) of zeros, never touched
    "narrower": [1],                  # fewer columns (a 1-D array becomes one value)
    "fewer": [1, 2],                  # fewer units (rows; both axes of a square array)
    "more": [1, 7],                   # more units
    "strided": [2, 3],                # the same values, every arg-th element of a larger array
    "fortran": [0],                   # the same values, Fortran-ordered
    "transposed": [0],                # the transpose (of a 2-D array)
    "read-only": [0],                 # the same values, not writable
    "value": ["nan", "inf", "-inf", "1e300", "-1", "0", "2", "2**62", "-2**63"],  # one element, a copy
    "in-place": ["nan", "inf", "-inf", "1e300", "-1", "0", "2", "dup"],  # one element, written in place
    "dtype": ["float32", "int64", "float64", ">f8", "bool", "complex128", "object", "uint64", "int8"],
    "other": ["list", "none", "scalar", "empty", "matrix", "3d"],
}
#: the values a counter may be given
COUNT_VALUES = ["-1", "0", "1", "2**53", "2**53+1", "2**63", "2**70", "1.5", "True", "np.int64(5)",
                "np.uint64(2**63)", "None", "'3'", "nan", "10**6"]
#: the values a parameter may be given (set_params on the fitted part)
PARAM_VALUES = ["-1", "0", "1", "2", "0.5", "1e-300", "1e308", "nan", "inf", "None", "'x'", "10**20",
                "True", "np.float64(0.25)", "same", "'constant'", "'hold'", "'forget'"]


def _number(text: str):
    """The value a case names (cases are JSON: ``"2**53+1"``, ``"np.uint64(2**63)"``, ``"nan"``)."""
    return eval(text, {"np": np, "nan": math.nan, "inf": math.inf})  # noqa: S307 (the cases above)


def mutate(det, target: str, kind: str, arg, seed: int) -> None:
    """Make ``target`` of the fitted filter ``det`` hostile (module docstring), past the fitted
    parts' lock, as tests.damaged does (this module also runs as a script, outside the package)."""
    with engine_writes(parts_of(det.clusterer_, det.synapse_)):
        _mutate(det, target, kind, arg, seed)


def _mutate(det, target: str, kind: str, arg, seed: int) -> None:
    owner_path, _, leaf = target.rpartition(".")
    owner = attribute(det, owner_path) if owner_path else det
    rng = np.random.default_rng(seed)
    if kind == "count":
        setattr(owner, leaf, _number(arg))
        return
    if kind == "param":
        value = getattr(owner, leaf) if arg == "same" else _number(arg)
        owner.set_params(**{leaf: value})
        return
    a = getattr(owner, leaf)
    if kind == "in-place":
        if a.size == 0:
            return
        index = tuple(int(rng.integers(0, k)) for k in a.shape)
        if arg == "dup":  # another element's value (a duplicate unit id, a repeated unit)
            a[index] = a.flat[int(rng.integers(0, a.size))]
        else:
            a[index] = _number(arg)
        return
    setattr(owner, leaf, _hostile_array(a, kind, arg, rng))


def _hostile_array(a: np.ndarray, kind: str, arg, rng):
    n = a.shape[0] if a.ndim else 0
    if kind == "wider":
        extra = np.full(a.shape[:-1] + (arg,) if a.ndim > 1 else (n, arg), 0.5, dtype=a.dtype)
        return np.concatenate([a if a.ndim > 1 else a[:, None], extra], axis=-1)
    if kind == "wide-zeros":
        return np.zeros((max(n, 1), arg), dtype=a.dtype)
    if kind == "narrower":
        return a[..., :-arg].copy() if a.ndim > 1 else np.array(a[0] if a.size else 0.0, dtype=a.dtype)
    if kind == "fewer":
        b = a[:max(n - arg, 0)]
        square = a.ndim == 2 and a.shape[0] == a.shape[1]
        return (b[:, :max(n - arg, 0)] if square else b).copy()
    if kind == "more":
        pad = [(0, arg)] + [(0, arg if a.ndim == 2 and a.shape[0] == a.shape[1] else 0)] * (a.ndim - 1)
        return np.pad(a, pad, mode="edge") if a.size else np.zeros((arg,) + a.shape[1:], a.dtype)
    if kind == "strided":
        big = np.zeros((n * arg,) + a.shape[1:], dtype=a.dtype)
        big[::arg] = a
        return big[::arg]
    if kind == "fortran":
        return np.asfortranarray(a)
    if kind == "transposed":
        return a.T.copy() if a.ndim == 2 else a[::-1].copy()
    if kind == "read-only":
        b = a.copy()
        b.setflags(write=False)
        return b
    if kind == "value":
        b = a.copy()
        if b.size:
            b[tuple(int(rng.integers(0, k)) for k in b.shape)] = _number(arg)
        return b
    if kind == "dtype":
        return a.astype(arg)
    if kind == "other":
        return {"list": lambda: a.tolist(), "none": lambda: None, "scalar": lambda: np.float64(1.0),
                "empty": lambda: a[:0].copy(), "matrix": lambda: np.asmatrix(a) if a.ndim == 2 else a.copy(),
                "3d": lambda: a[..., None].copy()}[arg]()
    raise AssertionError(kind)


# ----------------------------------------------------------------------------- a case
def run_case(case: dict, folder: str) -> dict:
    """The outcome of ``case`` (module docstring) under the engine this process uses."""
    original = fitted(case["pair"], folder)
    det = copy.deepcopy(original)
    out: dict = {"engine": type(vars(original)["_engine"]).__name__}
    if case["warm"]:
        det.score_learn_one(CALL[0].copy())
    out["mutation"] = _outcome(lambda: mutate(det, case["target"], case["kind"], case["arg"], case["seed"]))
    for call in case["calls"]:
        out.setdefault("calls", []).append(_outcome(lambda call=call: _call(det, call)))
    out["state"] = digest(det)
    return out


def _call(det, call: str):
    if call in ("score_one", "score_learn_one"):
        return getattr(det, call)(CALL[1].copy())
    return getattr(det, call)(CALL[2:])


def _outcome(run) -> list:
    try:
        result = run()
    except Exception as exc:  # the error is the outcome compared
        return ["error", type(exc).__name__, str(exc)]
    if result is None:
        return ["ok"]
    return ["ok", np.asarray(result, dtype=np.float64).tobytes().hex()]


def digest(det) -> str:
    """A digest of the values of the fitted parts' state (arrays by shape, type and values,
    whatever their layout; other values by their repr)."""
    h = hashlib.sha256()
    for part in (det.clusterer_, det.synapse_):
        for name in sorted(vars(part)):
            if not name.endswith("_") or name.startswith("_"):
                continue
            value = vars(part)[name]
            if hasattr(value, "get_params"):
                value = {k: v for k, v in vars(value).items() if k.endswith("_") and not k.startswith("_")}
                value = sorted((k, _text(v)) for k, v in value.items())
            h.update(f"{name}={_text(value)};".encode())
    return h.hexdigest()


def _text(value) -> str:
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        return str(int(value))  # a counter by its value: the compiled engine writes them back as ints
    if type(value) is np.ndarray and value.dtype != object:
        flat = value.reshape(-1)
        if flat.size > 2**20:  # the hostile (units, 10**7): its ends (copying it whole takes 8 GB)
            flat = np.concatenate([flat[:2**16], flat[-2**16:]])
        return f"{value.shape}{value.dtype}{hashlib.sha256(np.ascontiguousarray(flat)).hexdigest()}"
    return repr(value)


# ----------------------------------------------------------------------------- the child
def serve() -> None:
    """The child: the plugins' folder as the first argument, then one case per line of stdin,
    one line of JSON per case on stdout."""
    folder = sys.argv[1]
    for line in sys.stdin:
        outcome = run_case(json.loads(line), folder)
        sys.stdout.write(json.dumps(outcome) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    serve()
