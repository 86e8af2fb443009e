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
                           # default: the first detector listed (never one chosen by the results)
    protocol = "holdout"   # or "exploration": every scan scored, then learned, in order
                           # (novelty.bench.exploration)
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
A detector that reads the ``points`` input (the habituating maps: the
robot's pose with each scan) gets it from every task that offers it, as if
the task said ``inputs = "points"``, under the task's own label
(:func:`task_for`); elsewhere its cells fail and say why.

The parts of a suite are in :mod:`novelty.bench.specs`, their checks against
the registries in :mod:`novelty.bench.spec_checks`, and the reading of a
suite file in :mod:`novelty.bench.suite_file` (:func:`~novelty.bench.load_suite`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..datasets import registry
from ..registry import RegistryError, of_kind
from .build import build_detector
from .spec_checks import check_detector, check_task, check_threshold, with_policy
from .specs import PROTOCOLS, Cell, DetectorSpec, SuiteError, TaskSpec, parse_seeds

__all__ = ["Suite"]


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
    skip_reasons: dict[str, str] = field(default_factory=dict)  # why each skipped entry was skipped

    @property
    def reference_label(self) -> str | None:
        """The detector the others are paired with: ``reference``, else the first detector listed."""
        if self.reference is not None:
            return self.reference
        return self.detectors[0].label if self.detectors else None

    @property
    def reference_how(self) -> str:
        """How :attr:`reference_label` was chosen, for the summary."""
        if self.reference is not None:
            return "the suite's `reference`."
        return ("the suite's first detector, a default that does not depend on the results (set `reference` in "
                "the suite or `--reference` to choose another).")

    def cells(self) -> list[Cell]:
        components = _resolve_components(self)
        layouts = {d.label: input_layout(d) for d in self.detectors}
        return [
            Cell(d, task_for(t, layouts[d.label]), s, self.threshold,
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
        self.seeds = parse_seeds(self.seeds, f"The seeds of suite {self.name!r}")
        check_threshold(self.threshold)
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
                self.detectors[i] = with_policy(spec, det)
        labels = [d.label for d in self.detectors]  # with their policies
        if self.reference is not None and self.reference not in labels:
            raise SuiteError(f"The reference {self.reference!r} is not a detector of suite {self.name!r}; "
                             f"expected one of {', '.join(labels)}.")
        tasks = [t.label for t in self.tasks]
        twice = sorted({x for x in tasks if tasks.count(x) > 1})
        if twice:
            raise SuiteError(f"Two tasks are named {twice[0]!r}; give each its own name "
                             "(name=... on the command line, label = \"...\" in a suite file).")
        for spec in self.tasks:
            check_task(spec)
        return self


def input_layout(spec: DetectorSpec) -> str | None:
    """The rows a detector reads when it says (``input_layout``, e.g. ``"points"``); None: any rows."""
    try:
        return getattr(build_detector(spec), "input_layout", None)
    except Exception:  # noqa: BLE001 - an unbuildable detector is refused by check() or fails in its cells
        return None


def task_for(task: TaskSpec, layout: str | None) -> TaskSpec:
    """``task`` as a detector that reads ``layout`` rows gets it.

    A detector that states its input (the habituating map reads the ``points``
    input: the robot's pose with each scan) gets a task that can give it
    (``inputs`` among its options) with ``inputs = layout``, under the same
    label, so that its rows line up with the other detectors' on the same
    scans and labels. A task given ``inputs`` by the suite, a task object, and a
    task without that option are left as they are (the detector then refuses
    rows it cannot read, in its cells).
    """
    if layout is None or task.data is not None or "inputs" in task.options:
        return task
    try:
        valid = registry.parameters(task.name)
    except RegistryError:
        return task
    if valid is None or "inputs" not in valid:
        return task
    return TaskSpec(task.name, {**task.options, "inputs": layout}, task.label)


def _resolve_components(suite: "Suite") -> tuple:
    """The registered objects a suite names, for worker processes to register.

    Names registered at run time in this process (a script's own detector, a
    test's task) are unknown to a fresh worker; the cell carries the objects
    (pickled by reference) and the worker registers what it lacks.
    """
    wanted = [("detector", d.name) for d in suite.detectors if d.instance is None]
    for d in suite.detectors:
        for part in ("clusterer", "synapse"):
            if isinstance(d.params.get(part), str):
                wanted.append((part, d.params[part]))
    wanted += [("dataset", t.name) for t in suite.tasks if t.data is None]
    found = []
    for kind, name in dict.fromkeys(wanted):
        if name in of_kind(kind):
            found.append((kind, name, of_kind(kind).get(name)))
    return tuple(found)
