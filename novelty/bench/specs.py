"""The parts of a benchmark suite: detector and task specifications and cells.

A :class:`DetectorSpec` names a detector of the registry with its parameters,
a :class:`TaskSpec` a task (a dataset with a train/test split) with its
options, and a :class:`Cell` one (detector, task, seed) run with its stable
id. :func:`detector_from_text` and :func:`task_from_text` read them from the
command line. :mod:`novelty.bench.suite` puts them together into a suite.
"""

from __future__ import annotations

import hashlib
import json
import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping

from .protocol import PROTOCOL_NAMES

__all__ = [
    "SuiteError",
    "DetectorSpec",
    "TaskSpec",
    "Cell",
    "parse_value",
    "parse_assignments",
    "detector_from_text",
    "task_from_text",
    "tasks_from_text",
    "expand_folder",
    "FOLDER_SUFFIXES",
    "parse_seeds",
    "format_value",
    "resolve_files",
    "FILES_TASK",
    "FILE_OPTIONS",
    "HARNESS_VERSION",
    "PROTOCOLS",
]

#: bumped when a change of the harness changes what a cell computes
HARNESS_VERSION = 1
#: how a cell trains and scores: :mod:`novelty.bench.holdout` and :mod:`novelty.bench.exploration`
PROTOCOLS = PROTOCOL_NAMES


class SuiteError(ValueError):
    """A suite that cannot be run: malformed, or naming unknown things."""


#: the task made from the user's own files (:func:`novelty.tasks.files.files`)
FILES_TASK = "files"
#: its options that name files, read relative to the suite file
FILE_OPTIONS = ("path", "test_path")
#: the options that name files of the tasks read from a recording, read relative to the suite file too
#: (a list, or a comma-separated text, of recordings each)
RECORDING_FILE_OPTIONS = {"recording": ("paths", "marks"), "inspection-objects": ("path", "objects"),
                          "exploration-objects": ("path", "objects")}
#: the files a folder given as a files task's path holds, one task each (ADBench's .npz, ODDS's .mat, CSV)
FOLDER_SUFFIXES = (".npz", ".mat", ".csv")


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


def parse_seeds(value: Any, where: str = "seeds") -> list[int]:
    """The seeds of a run from a count, a list, or the command line's text.

    A count ``n >= 1`` (an int, or text like ``"3"``) means seeds ``0 .. n-1``;
    a list of non-negative ints, or text with commas (``"0,1,2"``; ``"5,"``
    for seed 5 alone), names them. Every way of giving seeds (a suite file,
    the command line, :func:`novelty.bench.run`) goes through here.

    >>> parse_seeds(3), parse_seeds([4, 7]), parse_seeds("0,2"), parse_seeds("5,")
    ([0, 1, 2], [4, 7], [0, 2], [5])
    """
    if isinstance(value, str):
        words = [w.strip() for w in value.split(",")]
        if not all(w.isdigit() for w in words if w) or not any(words):
            raise SuiteError(f"{where} must be a count like 3 (seeds 0, 1, 2) or a list like 0,1,2 "
                             f"(one seed: '5,'); got {value!r}.")
        value = [int(w) for w in words if w] if len(words) > 1 else int(words[0])
    if isinstance(value, int) and not isinstance(value, bool):
        if value < 1:
            raise SuiteError(f"{where} = {value} is a count of seeds and must be at least 1 "
                             "(for seed 0 alone, give the list [0], or '0,' on the command line).")
        return list(range(value))
    if isinstance(value, range):
        value = list(value)
    if not isinstance(value, (list, tuple)) or not value:
        raise SuiteError(f"{where} must be a non-empty list of integers or a count; got {value!r}.")
    for seed in value:
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise SuiteError(f"Seeds must be non-negative integers; got {seed!r}.")
    if len(set(value)) != len(value):
        raise SuiteError(f"{where} names a seed twice: {list(value)!r}.")
    return list(value)


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


def format_value(value: Any) -> str:
    """A parameter value as a label shows it: a string as is, anything else as compact JSON."""
    return value if isinstance(value, str) else _canonical(value)


# ------------------------------------------------------------------- specs
@dataclass(frozen=True)
class DetectorSpec:
    """A detector by registry name with its parameters and a display label."""

    name: str
    params: Mapping[str, Any] = field(default_factory=dict)
    label: str = ""
    #: how the detector learns under the exploration protocol
    #: (:mod:`novelty.bench.exploration.prequential`); "" for its default
    policy: str = ""
    #: a detector object given to :func:`novelty.bench.run` instead of a registry
    #: name; each cell runs an unfitted copy of it (``sklearn.base.clone``)
    instance: Any = field(default=None, repr=False, compare=False)

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
    #: a task object (a Dataset) given to :func:`novelty.bench.run` instead of a
    #: registry name; every seed runs on it as it is
    data: Any = field(default=None, repr=False, compare=False)

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
    #: "holdout" (train, freeze, score) or "exploration" (:mod:`novelty.bench.exploration`)
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
        """A short stable hash of the cell as the suite writes it (the resume key).

        A preset's name hashes the same whatever it resolves to; a resume
        also compares each row's :func:`~novelty.bench.definition.definition_digest`.
        """
        return hashlib.sha256(_canonical(self.key).encode()).hexdigest()[:16]


def resolve_files(options: dict, base: Path | None, task: str = FILES_TASK) -> dict:
    """The options of ``task`` that name files made absolute against the suite's folder (a suite runs from
    anywhere): the ``files`` task's :data:`FILE_OPTIONS`, a recording task's :data:`RECORDING_FILE_OPTIONS`.

    >>> resolve_files({"paths": "mon.bag,tue.bag", "places": 1.0}, Path("/runs"), "recording")
    {'paths': '/runs/mon.bag,/runs/tue.bag', 'places': 1.0}
    """
    if base is None:
        return options
    if task == FILES_TASK:
        return {k: str(base / v) if k in FILE_OPTIONS and isinstance(v, str) else v for k, v in options.items()}
    named = RECORDING_FILE_OPTIONS.get(task, ())
    return {k: _resolved(v, base) if k in named else v for k, v in options.items()}


def _resolved(value, base: Path):
    """A file name, a comma-separated text of them or a list of them, each against ``base``; anything else
    (objects given as tables, say) as it is."""
    if isinstance(value, str):
        if "," in value and not (base / value).exists():   # as the command line gives a list
            return ",".join(str(base / v.strip()) for v in value.split(","))
        return str(base / value)
    if isinstance(value, list) and all(isinstance(v, str) for v in value):
        return [str(base / v) for v in value]
    return value


def expand_folder(spec: TaskSpec) -> list[TaskSpec]:
    """A ``files`` task whose ``path`` is a folder: one task for each data file in it (``[spec]`` otherwise).

    The files are those ending in :data:`FOLDER_SUFFIXES`, in the order of
    their names, each a task labelled by its name without the extension and
    given the folder task's other options (a benchmark's protocol).
    """
    path = spec.options.get("path")
    if spec.name != FILES_TASK or not isinstance(path, str) or not Path(path).is_dir():
        return [spec]
    if spec.label not in (FILES_TASK, Path(path).stem, Path(path).name):
        raise SuiteError(f"Task {spec.label!r}: {path} is a folder, one task a file, each named by its file; "
                         "a name for the folder is not used (name a file's task by giving its path).")
    found = sorted(p for p in Path(path).iterdir() if p.suffix.lower() in FOLDER_SUFFIXES and p.is_file())
    if not found:
        raise SuiteError(f"Task folder {path} holds no data file ({', '.join(FOLDER_SUFFIXES)}).")
    return [TaskSpec(FILES_TASK, {**spec.options, "path": str(p)}, p.stem) for p in found]


# ------------------------------------------------------------ command line
def detector_from_text(text: str) -> DetectorSpec:
    """``"hsom n_rows=5 alpha=1.2"`` -> a :class:`DetectorSpec` (command line)."""
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
    """``"inspection-easy n_scans=200"`` -> a :class:`TaskSpec` (command line).

    ``name=`` is the task's name in every table, file and plot (default: the
    registry name; for ``files``, the file's name without its extension).

    >>> task_from_text("files path=/data/lab-a.csv label=novel").label
    'lab-a'
    >>> task_from_text("files path=/data/a.csv name=corridor").label
    'corridor'
    """
    try:
        words = shlex.split(text)
    except ValueError as exc:
        raise SuiteError(f"Cannot read task {text!r}: {exc}.") from None
    if not words:
        raise SuiteError("An empty --task was given.")
    options = parse_assignments(words[1:], "task option")
    label = options.pop("name", None)
    if label is not None and (not isinstance(label, str) or not label.strip()):
        raise SuiteError(f"Task {text!r}: name= must be a non-empty text; got {label!r}.")
    if words[0] == FILES_TASK:
        if label is None and isinstance(options.get("path"), str):
            label = Path(options["path"]).stem
        options = resolve_files(options, Path.cwd())
    return TaskSpec(words[0], options, label or "")


def tasks_from_text(text: str) -> list[TaskSpec]:
    """:func:`task_from_text`, a folder of data files given as ``files path=DIR`` read as one task a file.

    >>> [t.label for t in tasks_from_text("inspection-easy n_scans=200")]
    ['inspection-easy']
    """
    return expand_folder(task_from_text(text))
