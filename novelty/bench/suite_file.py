"""Reading a suite file: TOML into a checked :class:`~novelty.bench.suite.Suite`.

:func:`load_suite` reads a file, :func:`suite_from_dict` parsed TOML; the
file's form is described in :mod:`novelty.bench.suite`.
"""

from __future__ import annotations

import importlib.util
import itertools
import sys
from pathlib import Path
from typing import Any

from .._atomic import not_regular
from ..datasets import registry as datasets
from ..registry import detectors as detector_registry
from . import river
from .specs import (FILES_TASK, DetectorSpec, SuiteError, TaskSpec, expand_folder, format_value, parse_seeds,
                    resolve_files)
from .suite import Suite

__all__ = ["load_suite", "suite_from_dict", "quick_suite_path"]


def _read_toml(path: Path) -> dict:
    if sys.version_info >= (3, 11):
        # the standard library reads TOML from Python 3.11; tomli before
        import tomllib
    else:  # pragma: no cover - Python 3.10
        try:
            import tomli as tomllib
        except ImportError:
            raise SuiteError(
                "Reading TOML suites on Python 3.10 needs the 'tomli' package (pip install tomli)."
            ) from None
    kind = not_regular(path)
    if kind is not None:  # a FIFO would block the read, a device never end
        raise SuiteError(f"Suite file {path} is {kind}, not a regular file.")
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except RecursionError:
        raise SuiteError(f"Suite file {path} nests its tables or arrays too deeply to read.") from None
    except FileNotFoundError:
        raise SuiteError(f"Suite file not found: {path}") from None
    except IsADirectoryError:
        raise SuiteError(f"Suite file {path} is a directory.") from None
    except tomllib.TOMLDecodeError as exc:
        raise SuiteError(f"Suite file {path} is not valid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise SuiteError(f"Suite file {path} is not UTF-8 text ({exc.reason}); "
                         "save it as UTF-8.") from None


def _table(value: Any, where: str) -> dict:
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise SuiteError(f"{where} must be a table ({{ name = value, ... }}); got {value!r}.")
    return value


def _entries(data: dict, key: str, where: str) -> list[dict]:
    entries = data.get(key, [])
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise SuiteError(f"{where}: '{key}' must be an array of tables ([[{key}]]).")
    return entries


def _known_keys(entry: dict, allowed: set[str], where: str) -> None:
    unknown = sorted(set(entry) - allowed)
    if unknown:
        raise SuiteError(f"{where}: unknown key {unknown[0]!r}; expected {', '.join(sorted(allowed))}.")


def _label(entry: dict, name: str, where: str) -> str:
    label = entry.get("label", name)
    if not isinstance(label, str) or not label.strip():
        raise SuiteError(f"{where}: label must be a non-empty string; got {label!r}.")
    return label


def _expand_detector(entry: dict, where: str) -> list[DetectorSpec]:
    _known_keys(entry, {"name", "params", "grid", "label", "optional", "policy"}, where)
    name = entry.get("name")
    if not isinstance(name, str) or not name:
        raise SuiteError(f"{where}: every detector needs a 'name' (a registry name).")
    params = _table(entry.get("params"), f"{where}: params")
    grid = _table(entry.get("grid"), f"{where}: grid")
    policy = entry.get("policy", "")
    label = _label(entry, f"{name} ({policy})" if policy else name, where)
    for key, values in grid.items():
        if not isinstance(values, list) or not values:
            raise SuiteError(f"{where}: grid value of {key!r} must be a non-empty array.")
        if key in params:
            raise SuiteError(f"{where}: {key!r} is both in params and in grid.")
    if not grid:
        return [DetectorSpec(name, params, label, policy)]
    keys = list(grid)
    specs = []
    for combo in itertools.product(*(grid[k] for k in keys)):
        values = dict(zip(keys, combo))
        suffix = ",".join(f"{k}={format_value(v)}" for k, v in values.items())
        specs.append(DetectorSpec(name, {**params, **values}, f"{label}[{suffix}]", policy))
    return specs


def unavailable(name: str) -> str | None:
    """Why the detector ``name`` cannot run here (None: it can): an extra or a plugin not installed."""
    if river.is_river(name):
        return None if river.installed() else "River is not installed (pip install 'novelty-habituation[river]')"
    if name not in detector_registry:
        return "not registered here"
    try:
        requires = getattr(detector_registry.get(name), "requires", ())
    except Exception as exc:  # noqa: BLE001 - a broken plugin is skipped, saying why
        return f"cannot be loaded ({type(exc).__name__}: {exc})"
    missing = [m for m in requires if importlib.util.find_spec(m) is None]
    if missing:
        return f"{missing[0]} is not installed (pip install 'novelty-habituation[{missing[0]}]')"
    return None


def _files_task(entry: dict, where: str, base: Path | None) -> TaskSpec:
    """``[[tasks]] path = "scans.csv"``: the ``files`` task on that file."""
    if entry.get("name", FILES_TASK) != FILES_TASK:
        raise SuiteError(f"{where}: a task with a 'path' is the {FILES_TASK!r} task; "
                         f"got name {entry['name']!r}.")
    path = entry["path"]
    if not isinstance(path, str) or not path:
        raise SuiteError(f"{where}: path must be a file name; got {path!r}.")
    options = _table(entry.get("options"), f"{where}: options")
    if "path" in options:
        raise SuiteError(f"{where}: give the path once (path = ..., not also in options).")
    return TaskSpec(FILES_TASK, resolve_files({"path": path, **options}, base),
                    entry.get("label", Path(path).stem))


def suite_from_dict(data: dict, source: str = "suite", base: Path | None = None) -> Suite:
    """Build and check a :class:`Suite` from parsed TOML (file paths relative to ``base``)."""
    _known_keys(data, {"suite", "detectors", "tasks"}, source)
    head = _table(data.get("suite"), f"{source}: [suite]")
    _known_keys(head, {"name", "seeds", "threshold", "memory", "description", "reference",
                       "protocol", "cell_timeout"},
                f"{source}: [suite]")
    seeds = parse_seeds(head.get("seeds", [0]), f"{source}: seeds")
    detectors: list[DetectorSpec] = []
    skipped: list[str] = []
    reasons: dict[str, str] = {}
    for i, entry in enumerate(_entries(data, "detectors", source)):
        where = f"{source}: detectors[{i}]"
        reason = unavailable(entry["name"]) if entry.get("optional") and isinstance(entry.get("name"), str) else None
        if reason:
            skipped.append(entry["name"])
            reasons[entry["name"]] = reason
            continue
        detectors.extend(_expand_detector(entry, where))
    tasks: list[TaskSpec] = []
    for i, entry in enumerate(_entries(data, "tasks", source)):
        where = f"{source}: tasks[{i}]"
        _known_keys(entry, {"name", "options", "label", "optional", "path"}, where)
        if "path" in entry:
            tasks.extend(expand_folder(_files_task(entry, where, base)))
            continue
        name = entry.get("name")
        if not isinstance(name, str) or not name:
            raise SuiteError(f"{where}: every task needs a 'name' (a dataset registry name) or a 'path'.")
        if entry.get("optional") and name not in datasets:
            skipped.append(name)
            reasons[name] = "not registered here"
            continue
        options = _table(entry.get("options"), f"{where}: options")
        options = resolve_files(options, base, name)
        tasks.extend(expand_folder(TaskSpec(name, options, _label(entry, name, where))))
    memory = head.get("memory", True)
    if not isinstance(memory, bool) and memory != "first-seed":
        raise SuiteError(f"{source}: memory must be true, false or \"first-seed\"; got {memory!r}.")
    reference = head.get("reference")
    if reference is not None and not isinstance(reference, str):
        raise SuiteError(f"{source}: reference must be a detector's label (a string); got {reference!r}.")
    suite = Suite(detectors, tasks, seeds, str(head.get("name", source)),
                  head.get("threshold", "max"), memory, skipped, reference,
                  head.get("protocol", "holdout"), head.get("cell_timeout"), reasons)
    return suite.check()


def load_suite(path) -> Suite:
    """Read and check a suite file."""
    path = Path(path)
    return suite_from_dict(_read_toml(path), source=path.name, base=path.parent.resolve())


def quick_suite_path() -> Path:
    """The embedded default suite of ``novelty bench --quick``."""
    return Path(__file__).with_name("suites") / "quick.toml"
