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

The parts of a suite are in :mod:`novelty.bench.specs`, their checks against
the registries in :mod:`novelty.bench.spec_checks`, and the reading of a
file's entries in :mod:`novelty.bench.suite_file`; their public names are
importable from here too.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..datasets import registry as datasets
from ..registry import detectors as detector_registry, of_kind
from .spec_checks import _check_threshold, _with_policy, check_detector, check_task  # noqa: F401
from .specs import (FILES_TASK, HARNESS_VERSION, PROTOCOLS, Cell, DetectorSpec, SuiteError,  # noqa: F401
                    TaskSpec, _resolved, detector_from_text, parse_assignments, parse_value, task_from_text)
from .suite_file import (_available, _entries, _expand_detector, _files_task, _known_keys, _label,
                         _read_toml, _table)

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


def _resolve_components(suite: Suite) -> tuple:
    """The registered objects a suite names, for worker processes to register.

    Names registered at run time in this process (a script's own detector, a
    test's task) are unknown to a fresh worker; the cell carries the objects
    (pickled by reference) and the worker registers what it lacks.
    """
    wanted = [("detector", d.name) for d in suite.detectors]
    for d in suite.detectors:
        for part in ("clusterer", "synapse"):
            if isinstance(d.params.get(part), str):
                wanted.append((part, d.params[part]))
    wanted += [("dataset", t.name) for t in suite.tasks]
    found = []
    for kind, name in dict.fromkeys(wanted):
        if name in of_kind(kind):
            found.append((kind, name, of_kind(kind).get(name)))
    return tuple(found)


def suite_from_dict(data: dict, source: str = "suite", base: Path | None = None) -> Suite:
    """Build and check a :class:`Suite` from parsed TOML (file paths relative to ``base``)."""
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
