"""A cell's task and detector, built the same way by every protocol and backend.

- :func:`load_task`: the task's dataset with the cell's seed (cached per
  process: datasets are immutable);
- :func:`make_detector`: the detector of the registry (or a River adapter),
  seeded with the cell's seed unless the suite set one;
- :func:`train_detector`: train as a robot does (stream the training scans,
  or ``fit`` a batch-only detector);
- :func:`resting_novelty`, :func:`n_units`: what the detector became;
- :func:`check_finite`: a NaN or infinite score fails the cell
  (:class:`CellError`).
"""

from __future__ import annotations

import functools
import inspect
import json

import numpy as np
from sklearn.base import clone

from .._validation import pass_timestamps
from ..datasets import load, registry
from ..io.scans.points import POSE_COLUMNS
from ..registry import detectors, of_kind
from . import river
from .specs import Cell, DetectorSpec

__all__ = ["load_task", "build_detector", "make_detector", "train_detector", "resting_novelty", "n_units", "check_finite",
           "check_raw_finite",
           "ensure_registered", "CellError"]


class CellError(ValueError):
    """A cell that ran but whose result cannot be used (reported without a source location)."""


def ensure_registered(components) -> None:
    """Register, in this (worker) process, the objects the parent resolved."""
    for kind, name, obj in components:
        kind_registry = of_kind(kind)
        try:
            if name in kind_registry and kind_registry.get(name) is obj:
                continue
        except Exception:  # noqa: BLE001 - a broken entry is replaced below
            pass
        kind_registry.register(name, obj, replace=True)


@functools.lru_cache(maxsize=16)  # a suite cycles through its seeds task by task
def _load_task_cached(name: str, factory, options_json: str, seed: int):
    options = json.loads(options_json)
    valid = registry.parameters(name)
    if "seed" not in options and (valid is None or "seed" in valid):
        options["seed"] = seed
    return load(name, **options)


def load_task(cell: Cell):
    """The cell's task (cached per process: datasets are immutable; a name registered again is loaded again)."""
    data = cell.task.data
    if data is not None:  # a task object given to the Python API, not registered
        return data.for_seed(cell.seed) if hasattr(data, "for_seed") else data
    return _load_task_cached(cell.task.name, registry.get(cell.task.name),
                             json.dumps(cell.task.options, sort_keys=True), cell.seed)


def build_detector(spec: DetectorSpec):
    """A new, unfitted detector as ``spec`` describes it (registry name, River adapter or object)."""
    if spec.instance is not None:
        return clone(spec.instance)
    make = river.make if river.is_river(spec.name) else detectors.make
    return make(spec.name, **spec.params)


def check_input_layout(det, data, label: str) -> None:
    """Refuse a task whose rows are not the input the detector reads (its ``input_layout``).

    The habituating maps read the ``points`` input (the robot's pose, the ring,
    the end points: :mod:`novelty.io.scans.points`), whose width alone cannot tell
    it from any other rows of ``3 + 3n`` values (the UCI sonar's 60). A task
    says what its rows are in ``metadata["inputs"]`` (a task given
    ``inputs="points"`` does), or names its columns (``metadata["columns"]``,
    or the ``sensor_columns`` of the user's own file) starting with the pose's.
    """
    layout = getattr(det, "input_layout", None)
    if layout is None:
        return
    meta = getattr(data, "metadata", None) or {}
    given = meta.get("inputs")
    if given == layout:
        return
    named = list(meta.get("columns") or meta.get("sensor_columns") or [])
    if given is None and layout == "points" and named[:len(POSE_COLUMNS)] == list(POSE_COLUMNS):
        return
    what = f"rows of the {given!r} input" if given is not None else "rows that do not say what they are"
    raise CellError(f"{type(det).__name__} reads rows of the {layout!r} input (the robot's pose with each scan); "
                    f"task {label!r} gives {what}. Give the task inputs={layout!r} if it has the robot's poses, or "
                    f"for rows of your own in that layout set metadata['inputs'] = {layout!r} (novelty.io.scans.points).")


def make_detector(cell: Cell):
    """The cell's detector, seeded with the cell's seed unless the suite (or the object) set one."""
    det = build_detector(cell.detector)
    params = cell.detector.params
    # a suite's parameter is set when named; an object's only when not None (its default)
    chosen = params.get("random_state") is not None if cell.detector.instance is not None \
        else "random_state" in params
    if not chosen and hasattr(det, "get_params") and "random_state" in det.get_params(deep=False):
        det.set_params(random_state=cell.seed)
    return det


def train_detector(det, X: np.ndarray, passes: int = 1, timestamps=None):
    """Train as the robot does: stream ``X`` ``passes`` times, or ``fit`` a batch-only detector.

    With ``timestamps`` (a task's time column), an online detector that takes
    them is given them; each further pass continues the clock, one typical
    step after the previous pass ended, as a robot driving the route again.
    """
    if not getattr(det, "supports_online", True):
        return det.fit(X)
    if timestamps is not None and "timestamps" not in inspect.signature(det.partial_fit).parameters:
        timestamps = None
    for k in range(passes):
        det.partial_fit(X, timestamps=None if timestamps is None else pass_timestamps(timestamps, k))
    return det


def resting_novelty(det) -> float:
    """The detector's resting novelty (0 for a detector without one)."""
    try:
        value = getattr(det, "resting_novelty", None)
    except Exception:  # noqa: BLE001 - a detector without a defined resting level
        value = None
    return 0.0 if value is None else float(value)


def n_units(det) -> float:
    """The number of units of the detector's network (NaN for a detector without units)."""
    for owner in (getattr(det, "clusterer_", None), det):
        n = getattr(owner, "n_units_", None) if owner is not None else None
        if n is not None:
            return int(n)
    return float("nan")


def check_finite(scores: np.ndarray, what: str, whose: str = "the detector scored") -> None:
    """A NaN or infinite score ranks nowhere: the cell fails rather than count on its other scans."""
    bad = int(np.count_nonzero(~np.isfinite(scores)))
    if bad:
        raise CellError(f"{whose} {bad} of {scores.size} {what} NaN or infinite")


def check_raw_finite(det, X: np.ndarray, what: str) -> None:
    """A detector's own score (``raw_novelty``, before calibration) must be finite too.

    The comparable scale maps +inf to 1, so a model that scores every test
    scan +inf (PyOD's PCA on a degenerate split) would give a constant
    novelty and a ROC AUC of 0.5 that measures nothing; the cell fails
    instead, saying how many scores were not finite.
    """
    raw = getattr(det, "raw_novelty", None)
    if raw is not None:
        check_finite(np.asarray(raw(X), dtype=np.float64), what, "the detector's own score (raw_novelty) was")
