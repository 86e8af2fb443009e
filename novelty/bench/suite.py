"""Benchmark suites: which detectors, on which tasks, with which seeds.

A suite is read from TOML or built from the command line, checked against the
registries (unknown names and parameters are refused before anything runs)
and expanded into :class:`Cell` objects, one per (detector, task, seed).

The TOML form::

    [suite]
    name = "quick"
    seeds = [0, 1]
    threshold = "max"      # or a quantile of the training novelty, e.g. 0.99
    memory = true          # peak memory by a second, traced run of each cell;
                           # "first-seed": of the cells of the first seed only
    reference = "parzen"   # optional: the detector (label) of the paired comparison;
                           # default: the detector ranked first
    protocol = "holdout"   # or "exploration": every scan scored, then learned, in order
                           # (novelty.bench.prequential)
    cell_timeout = 600     # optional: seconds a cell may run before it is stopped and
                           # recorded as failed (cells then run in worker processes)

    [[detectors]]
    name = "hsom"                               # registry name
    params = { n_rows = 5 }                     # optional
    grid = { alpha = [1.05, 1.2] }              # optional: one detector per value
    label = "hsom-5x5"                          # optional: name in the tables
    optional = true                             # optional: skip if not registered
    policy = "refit"                            # optional, protocol "exploration" only:
                                                # online, frozen, refit, window=N

    [[tasks]]
    name = "inspection-easy"
    options = { n_scans = 200 }                 # optional, given to the task

    [[tasks]]                                   # the user's own scans: the task "files"
    path = "scans.csv"                          # relative to the suite file
    options = { label = "novel", train_rows = 500, columns = "sonar*" }
    label = "my-corridor"                       # optional (default: the file's name)

Every detector entry expands over the Cartesian product of its ``grid``;
the label of each then carries its grid values, ``hsom-5x5[alpha=1.2]``.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping

__all__ = [
    "SuiteError",
    "DetectorSpec",
    "TaskSpec",
    "Cell",
    "Suite",
    "parse_value",
    "parse_assignments",
    "load_suite",
    "quick_suite_path",
]

#: bumped when a change of the harness changes what a cell computes
HARNESS_VERSION = 1
#: how a cell trains and scores: see :mod:`novelty.bench.cell` and :mod:`novelty.bench.prequential`
PROTOCOLS = ("holdout", "exploration")


class SuiteError(ValueError):
    """A suite that cannot be run: malformed, or naming unknown things."""


# ------------------------------------------------------------------ values
def parse_value(text: str) -> Any:
    """A command-line value: JSON where it parses, else the string itself.

    ``5`` -> 5, ``1.05`` -> 1.05, ``true``/``True`` -> True, ``null``/``None``
    -> None, ``[3, 4]`` -> [3, 4], ``som`` -> "som".

    >>> [parse_value(v) for v in ("5", "1.05", "True", "som", "[3, 4]")]
    [5, 1.05, True, 'som', [3, 4]]
    """
    aliases = {"True": True, "False": False, "None": None}
    if text in aliases:
        return aliases[text]
    try:
        return json.loads(text)
    except ValueError:
        return text


def parse_assignments(items: Iterable[str], what: str = "parameter") -> dict[str, Any]:
    """``["k=v", ...]`` -> ``{k: parse_value(v)}``; a bad item is a :class:`SuiteError`."""
    out: dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise SuiteError(f"A {what} must be written name=value; got {item!r}.")
        out[key] = parse_value(value.strip())
    return out


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), default=str)


def _format_value(value: Any) -> str:
    return value if isinstance(value, str) else _canonical(value)


# ------------------------------------------------------------------- specs
@dataclass(frozen=True)
class DetectorSpec:
    """A detector by registry name with its parameters and a display label."""

    name: str
    params: Mapping[str, Any] = field(default_factory=dict)
    label: str = ""
    #: how the detector learns under the exploration protocol
    #: (:mod:`novelty.bench.prequential`); "" for its default
    policy: str = ""

    def __post_init__(self):
        object.__setattr__(self, "params", dict(self.params))
        if not self.label:
            object.__setattr__(self, "label", self.name)

    def to_dict(self) -> dict:
        out = {"name": self.name, "params": dict(self.params), "label": self.label}
        if self.policy:  # only when set, so that earlier runs keep their cell ids
            out["policy"] = self.policy
        return out


@dataclass(frozen=True)
class TaskSpec:
    """A task (a dataset with a train/test split) by registry name with options."""

    name: str
    options: Mapping[str, Any] = field(default_factory=dict)
    label: str = ""

    def __post_init__(self):
        object.__setattr__(self, "options", dict(self.options))
        if not self.label:
            object.__setattr__(self, "label", self.name)

    def to_dict(self) -> dict:
        return {"name": self.name, "options": dict(self.options), "label": self.label}


@dataclass(frozen=True)
class Cell:
    """One unit of work: a detector on a task with a seed.

    A cell is a pure function of these fields (see :func:`novelty.bench.cell.run_cell`):
    the seed is given to the task as ``seed`` and to the detector as
    ``random_state``, unless the suite sets them itself.
    """

    detector: DetectorSpec
    task: TaskSpec
    seed: int
    threshold: Any = "max"
    memory: bool = True
    #: "holdout" (train, freeze, score) or "exploration" (:mod:`novelty.bench.prequential`)
    protocol: str = "holdout"
    #: seconds the cell may run (None: no limit); not part of what it computes, nor of its id
    timeout: float | None = None
    #: registry objects the parent process resolved, so that worker processes
    #: know names registered at run time: ((kind, name, object), ...)
    components: tuple = ()

    @property
    def key(self) -> dict:
        key = {
            "harness": HARNESS_VERSION,
            "detector": self.detector.to_dict(),
            "task": self.task.to_dict(),
            "seed": self.seed,
            "threshold": self.threshold,
        }
        if self.protocol != "holdout":
            key["protocol"] = self.protocol
        return key

    @property
    def id(self) -> str:
        """A short stable hash of what the cell computes (the resume key)."""
        return hashlib.sha256(_canonical(self.key).encode()).hexdigest()[:16]


@dataclass
class Suite:
    """Detectors x tasks x seeds, checked and ready to expand into cells."""

    detectors: list[DetectorSpec]
    tasks: list[TaskSpec]
    seeds: list[int] = field(default_factory=lambda: [0])
    name: str = "suite"
    threshold: Any = "max"
    memory: bool | str = True
    skipped: list[str] = field(default_factory=list)  # optional entries not registered
    reference: str | None = None  # label of the detector the others are paired with
    protocol: str = "holdout"
    cell_timeout: float | None = None  # seconds; None: no limit

    def cells(self) -> list[Cell]:
        components = _resolve_components(self)
        return [
            Cell(d, t, s, self.threshold,
                 self.memory is True or (self.memory == "first-seed" and s == self.seeds[0]),
                 self.protocol, self.cell_timeout, components)
            for t in self.tasks
            for d in self.detectors
            for s in self.seeds
        ]

    def check(self) -> "Suite":
        """Refuse unknown names and parameters now rather than in every cell."""
        if not self.detectors:
            raise SuiteError(f"Suite {self.name!r} has no detectors.")
        if not self.tasks:
            raise SuiteError(f"Suite {self.name!r} has no tasks.")
        if not self.seeds:
            raise SuiteError(f"Suite {self.name!r} has no seeds.")
        for seed in self.seeds:
            if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
                raise SuiteError(f"Seeds must be non-negative integers; got {seed!r}.")
        _check_threshold(self.threshold)
        if self.protocol not in PROTOCOLS:
            raise SuiteError(f"Unknown protocol {self.protocol!r}; expected one of {', '.join(PROTOCOLS)}.")
        timeout = self.cell_timeout
        if timeout is not None and (isinstance(timeout, bool) or not isinstance(timeout, (int, float))
                                    or not 0 < timeout < float("inf")):
            raise SuiteError(f"cell_timeout must be a positive number of seconds; got {timeout!r}.")
        labels = [d.label for d in self.detectors]
        dupes = sorted({x for x in labels if labels.count(x) > 1})
        if dupes:
            raise SuiteError(f"Two detectors are labelled {dupes[0]!r}; give them distinct 'label's.")
        for i, spec in enumerate(self.detectors):
            det = check_detector(spec)
            if spec.policy and self.protocol != "exploration":
                raise SuiteError(f"Detector {spec.label!r} has a policy; policies are for "
                                 "protocol = \"exploration\".")
            if self.protocol == "exploration":
                self.detectors[i] = _with_policy(spec, det)
        labels = [d.label for d in self.detectors]  # with their policies
        if self.reference is not None and self.reference not in labels:
            raise SuiteError(f"The reference {self.reference!r} is not a detector of suite {self.name!r}; "
                             f"expected one of {', '.join(labels)}.")
        for spec in self.tasks:
            check_task(spec)
        return self


def _check_threshold(rule: Any) -> None:
    if rule == "max":
        return
    if isinstance(rule, (int, float)) and not isinstance(rule, bool) and 0 < rule <= 1:
        return
    raise SuiteError(f"threshold must be \"max\" or a quantile in (0, 1]; got {rule!r}.")


def check_detector(spec: DetectorSpec):
    """Build the detector once: the registry refuses unknown names and parameters."""
    from ..registry import RegistryError, detectors
    from . import river

    try:
        make = river.make if river.is_river(spec.name) else detectors.make
        det = make(spec.name, **spec.params)
        _validate_tree(det)
    except RegistryError as exc:
        raise SuiteError(str(exc)) from None
    except (ValueError, TypeError, ImportError) as exc:
        raise SuiteError(f"Detector {spec.label!r}: {exc}") from None
    return det


def _validate_tree(component) -> None:
    """Run the parameter checks of a component and of the components it holds.

    A ``random_state`` is checked here too (estimators check it only when
    they fit, which would fail every cell): None or an int seed.
    """
    validate = getattr(component, "_validate_params", None)
    if validate is not None:
        validate()
    get_params = getattr(component, "get_params", None)
    if get_params is not None:
        for key, value in get_params(deep=False).items():
            if key == "random_state" and value is not None and (
                    isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 2**32):
                raise ValueError(f"random_state must be None or an int seed in [0, 2**32); got {value!r}.")
            if hasattr(value, "_validate_params"):
                _validate_tree(value)


def _with_policy(spec: DetectorSpec, det) -> DetectorSpec:
    """The spec with its policy checked; a batch-only detector's default shown in its label."""
    # imported here: the exploration harness pulls in the sonar simulator, which
    # the hold-out protocol never needs
    from .prequential import check_policy, default_policy

    if spec.policy:
        check_policy(spec.policy, det)
        return spec
    policy = default_policy(det)
    if policy == "online":
        return spec
    return DetectorSpec(spec.name, spec.params, f"{spec.label} ({policy})", policy)


def check_task(spec: TaskSpec) -> None:
    """Check a task's name and option names without loading any data."""
    from ..datasets import registry
    from ..registry import RegistryError, check_parameters

    try:
        valid = registry.parameters(spec.name)
        if valid is not None:
            check_parameters(f"task '{spec.name}'", spec.options, valid)
    except RegistryError as exc:
        raise SuiteError(str(exc)) from None
    if spec.name == FILES_TASK:
        if "path" not in spec.options:
            raise SuiteError(f"Task {spec.label!r}: the {FILES_TASK!r} task needs path= (a .csv or .npz file).")
        for key in _FILE_OPTIONS:
            if key in spec.options and not Path(str(spec.options[key])).is_file():
                raise SuiteError(f"Task {spec.label!r}: data file not found: {spec.options[key]}")


def _resolve_components(suite: Suite) -> tuple:
    """The registered objects a suite names, for worker processes to register.

    Names registered at run time in this process (a script's own detector, a
    test's task) are unknown to a fresh worker; the cell carries the objects
    (pickled by reference) and the worker registers what it lacks.
    """
    from ..datasets import registry as datasets
    from ..registry import clusterers, detectors, synapses

    wanted = [("detector", d.name) for d in suite.detectors]
    for d in suite.detectors:
        for part in ("clusterer", "synapse"):
            if isinstance(d.params.get(part), str):
                wanted.append((part, d.params[part]))
    wanted += [("dataset", t.name) for t in suite.tasks]
    registries = {"detector": detectors, "clusterer": clusterers, "synapse": synapses,
                  "dataset": datasets}
    found = []
    for kind, name in dict.fromkeys(wanted):
        if name in registries[kind]:
            found.append((kind, name, registries[kind].get(name)))
    return tuple(found)


# ------------------------------------------------------------------ reading
def _read_toml(path: Path) -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        try:
            import tomli as tomllib
        except ImportError:
            raise SuiteError(
                "Reading TOML suites on Python 3.10 needs the 'tomli' package (pip install tomli)."
            ) from None
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
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
        suffix = ",".join(f"{k}={_format_value(v)}" for k, v in values.items())
        specs.append(DetectorSpec(name, {**params, **values}, f"{label}[{suffix}]", policy))
    return specs


def _available(name: str, detector_registry) -> bool:
    from . import river

    return river.installed() if river.is_river(name) else name in detector_registry


#: the task made from the user's own files (:func:`novelty.datasets.files.files`)
FILES_TASK = "files"
#: its options that name files, read relative to the suite file
_FILE_OPTIONS = ("path", "test_path")


def _resolved(options: dict, base: Path | None) -> dict:
    """File options made absolute against the suite's folder (a suite runs from anywhere)."""
    if base is None:
        return options
    return {k: str(base / v) if k in _FILE_OPTIONS and isinstance(v, str) else v for k, v in options.items()}


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
    return TaskSpec(FILES_TASK, _resolved({"path": path, **options}, base),
                    entry.get("label", Path(path).stem))


def suite_from_dict(data: dict, source: str = "suite", base: Path | None = None) -> Suite:
    """Build and check a :class:`Suite` from parsed TOML (file paths relative to ``base``)."""
    from ..datasets import registry as datasets
    from ..registry import detectors as detector_registry

    _known_keys(data, {"suite", "detectors", "tasks"}, source)
    head = _table(data.get("suite"), f"{source}: [suite]")
    _known_keys(head, {"name", "seeds", "threshold", "memory", "description", "reference",
                       "protocol", "cell_timeout"},
                f"{source}: [suite]")
    seeds = head.get("seeds", [0])
    if isinstance(seeds, int) and not isinstance(seeds, bool):
        if seeds < 1:
            raise SuiteError(f"{source}: seeds = {seeds} is a count of seeds and must be at least 1 "
                             "(for seed 0 alone, write seeds = [0]).")
        seeds = list(range(seeds))
    if not isinstance(seeds, list):
        raise SuiteError(f"{source}: seeds must be an array of integers or a count.")
    detectors: list[DetectorSpec] = []
    skipped: list[str] = []
    for i, entry in enumerate(_entries(data, "detectors", source)):
        where = f"{source}: detectors[{i}]"
        if entry.get("optional") and isinstance(entry.get("name"), str) \
                and not _available(entry["name"], detector_registry):
            skipped.append(entry["name"])
            continue
        detectors.extend(_expand_detector(entry, where))
    tasks: list[TaskSpec] = []
    for i, entry in enumerate(_entries(data, "tasks", source)):
        where = f"{source}: tasks[{i}]"
        _known_keys(entry, {"name", "options", "label", "optional", "path"}, where)
        if "path" in entry:
            tasks.append(_files_task(entry, where, base))
            continue
        name = entry.get("name")
        if not isinstance(name, str) or not name:
            raise SuiteError(f"{where}: every task needs a 'name' (a dataset registry name) or a 'path'.")
        if entry.get("optional") and name not in datasets:
            skipped.append(name)
            continue
        options = _table(entry.get("options"), f"{where}: options")
        if name == FILES_TASK:
            options = _resolved(options, base)
        tasks.append(TaskSpec(name, options, _label(entry, name, where)))
    memory = head.get("memory", True)
    if not isinstance(memory, bool) and memory != "first-seed":
        raise SuiteError(f"{source}: memory must be true, false or \"first-seed\"; got {memory!r}.")
    reference = head.get("reference")
    if reference is not None and not isinstance(reference, str):
        raise SuiteError(f"{source}: reference must be a detector's label (a string); got {reference!r}.")
    suite = Suite(detectors, tasks, list(seeds), str(head.get("name", source)),
                  head.get("threshold", "max"), memory, skipped, reference,
                  head.get("protocol", "holdout"), head.get("cell_timeout"))
    return suite.check()


def load_suite(path) -> Suite:
    """Read and check a suite file."""
    path = Path(path)
    return suite_from_dict(_read_toml(path), source=path.name, base=path.parent.resolve())


def quick_suite_path() -> Path:
    """The embedded default suite of ``novelty bench --quick``."""
    return Path(__file__).with_name("suites") / "quick.toml"


def detector_from_text(text: str) -> DetectorSpec:
    """``"hsom n_rows=5 alpha=1.2"`` -> a :class:`DetectorSpec` (command line)."""
    import shlex

    try:
        words = shlex.split(text)
    except ValueError as exc:
        raise SuiteError(f"Cannot read detector {text!r}: {exc}.") from None
    if not words:
        raise SuiteError("An empty --detector was given.")
    params = parse_assignments(words[1:])
    label = words[0] if not params else f"{words[0]}[{','.join(words[1:])}]"
    return DetectorSpec(words[0], params, label)


def task_from_text(text: str) -> TaskSpec:
    """``"inspection-easy n_scans=200"`` -> a :class:`TaskSpec` (command line)."""
    import shlex

    try:
        words = shlex.split(text)
    except ValueError as exc:
        raise SuiteError(f"Cannot read task {text!r}: {exc}.") from None
    if not words:
        raise SuiteError("An empty --task was given.")
    options = parse_assignments(words[1:], "task option")
    if words[0] == FILES_TASK:
        options = _resolved(options, Path.cwd())
    return TaskSpec(words[0], options)
