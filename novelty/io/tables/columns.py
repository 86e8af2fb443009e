"""Which column of a file of scans is what: sensors, label, time, route (rules in :mod:`novelty.io.tables.scan_file`)."""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np

__all__ = ["Layout", "plan_columns", "is_ros_export", "is_points_file", "LABEL_COLUMNS", "TIME_COLUMNS", "ROUTE_COLUMNS",
           "TEXT_COLUMNS", "cell_text"]

#: columns found by name that are never sensors
LABEL_COLUMNS = ("y", "label")
TIME_COLUMNS = ("time", "timestamp", "field.header.stamp", "%time")
ROUTE_COLUMNS = ("distance", "run", "split")
#: further per-scan columns of the project's own exports (text, never sensors)
TEXT_COLUMNS = ("features", "class", "row_index")


def is_ros_export(names: Sequence[str]) -> bool:
    """A ``rostopic echo -p`` export: a ``%time`` column or ``field.*`` columns."""
    return "%time" in names or any(n.startswith("field.") for n in names)


def is_points_file(names: Sequence[str]) -> bool:
    """A file of the ``points`` input (:mod:`novelty.io.scans.points`): its header is the layout's own names,
    in order, among columns of other roles (a ``label``, a time, the route's, text).

    Its ``y`` is the robot's position, not a label, and every column of the layout is an input.

    >>> is_points_file(["time", "x", "y", "heading", "near_0", "x_0", "y_0", "label"])
    True
    >>> is_points_file(["x", "y", "label"])
    False
    """
    # deferred: novelty.maps loads the detectors, which the command line's start does not need
    from ..scans.points import points_columns

    roles = {n.lower() for n in ("label",) + TIME_COLUMNS + ROUTE_COLUMNS + TEXT_COLUMNS}
    core = [str(n).strip().lower() for n in names if str(n).strip().lower() not in roles]
    extra = len(core) - 3
    return extra >= 3 and extra % 3 == 0 and core == points_columns(extra // 3)


def _is_ros_header(name: str) -> bool:
    return name == "%time" or name.startswith("field.header.")


def _nanoseconds(name: str) -> bool:
    return name == "%time" or name.endswith(".stamp")


@dataclass(frozen=True)
class Layout:
    """Which column of a file is what (indices into the file's columns)."""

    names: tuple[str, ...]
    sensors: tuple[int, ...]
    label: int | None = None
    time: int | None = None
    distance: int | None = None
    run: int | None = None
    split: int | None = None

    @property
    def sensor_names(self) -> list[str]:
        return [self.names[j] for j in self.sensors]

    @property
    def time_scale(self) -> float:
        """Seconds per unit of the time column (ROS stamps are nanoseconds)."""
        return 1e-9 if self.time is not None and _nanoseconds(self.names[self.time]) else 1.0

    def column(self, j: int) -> str:
        """Column ``j`` as a message names it: ``column 'us05'``, ``column 'y' (the label)``."""
        name = self.names[j]
        role = next((r for r in ("label", "time", "distance", "run", "split") if getattr(self, r) == j), None)
        return f"column {name!r}" if role in (None, name.lower()) else f"column {name!r} ({'the ' + role})"

    def not_a_number(self, j: int, cell, where: str) -> ValueError:
        """The error for ``cell`` of column ``j``, at ``where`` (a file and its line or row), not a number."""
        message = f"{where}, {self.column(j)}: expected a number, got {cell_text(cell)}"
        if j not in self.sensors:
            return ValueError(message + ".")
        example = ", e.g. 'field.ranges*'" if is_ros_export(self.names) else ""
        return ValueError(f"{message}; choose the sensor columns with columns= (--columns){example}.")


def cell_text(cell) -> str:
    """What a cell that is not a number holds, for a message: ``text 'n/a'`` or ``an empty cell``."""
    text = str(cell).strip()
    return f"text {text[:30]!r}" if text else "an empty cell"

def _find(names: Sequence[str], spec, what: str) -> list[int]:
    """Indices of the columns ``spec`` names: a name, a pattern, or a 0-based index."""
    if isinstance(spec, (int, np.integer)) and not isinstance(spec, bool) \
            or isinstance(spec, str) and spec.strip().lstrip("-").isdigit():
        j = int(spec)
        if not 0 <= j < len(names):
            raise ValueError(f"{what}: column index {j} is out of range; the file has {len(names)} "
                             f"columns (0 to {len(names) - 1}).")
        return [j]
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"{what}: expected a column name, pattern or index; got {spec!r}.")
    spec = spec.strip()
    if spec in names:
        return [names.index(spec)]
    found = [j for j, n in enumerate(names) if fnmatch.fnmatchcase(n, spec)]
    if not found:
        shown = ", ".join(names[:12]) + (", ..." if len(names) > 12 else "")
        raise ValueError(f"{what}: no column {spec!r}; the file has {shown}.")
    return found


def _one(names: Sequence[str], spec, what: str) -> int | None:
    if spec is None:
        return None
    found = _find(names, spec, what)
    if len(found) != 1:
        raise ValueError(f"{what}: {spec!r} names {len(found)} columns; expected one.")
    return found[0]


def _by_default(names: Sequence[str], candidates: Iterable[str]) -> int | None:
    lowered = [n.lower() for n in names]
    return next((lowered.index(c) for c in candidates if c in lowered), None)


def _column_list(columns) -> list:
    if isinstance(columns, str):
        return [c for c in columns.split(",") if c.strip()]
    if isinstance(columns, (list, tuple)):
        return list(columns)
    return [columns]


def plan_columns(names: Sequence[str], columns=None, label=None, time=None, split=None) -> Layout:
    """Decide which column is what (see the module docstring); names alone decide."""
    names = tuple(names)
    # in a file of the points input, y is the robot's position: only a column named label is a label
    labels = ("label",) if is_points_file(names) else LABEL_COLUMNS
    label_j = _one(names, label, "label") if label is not None else _by_default(names, labels)
    time_j = _one(names, time, "time") if time is not None else _by_default(names, TIME_COLUMNS)
    split_j = _one(names, split, "split") if split is not None else _by_default(names, ("split",))
    distance_j, run_j = _by_default(names, ("distance",)), _by_default(names, ("run",))
    roles = {j for j in (label_j, time_j, split_j, distance_j, run_j) if j is not None}
    if columns is not None:
        chosen = [j for spec in _column_list(columns) for j in _find(names, spec, "columns")]
        sensors = list(dict.fromkeys(chosen))
        taken = sorted(roles & set(sensors))
        if taken:
            raise ValueError(f"columns: {names[taken[0]]!r} is the label, time, distance, run or split "
                             "column, not a sensor.")
    else:
        if is_ros_export(names):
            fields = [n for n in names if not _is_ros_header(n)]
            ranges = [n for n in fields if n.startswith("field.ranges")]
            example = "field.ranges*" if ranges else ",".join(fields[:3])
            raise ValueError("This is a ROS 'rostopic echo -p' export: its header columns (%time, "
                             "field.header.*) are not sensor readings. Choose the sensor columns with "
                             f"columns= (--columns), e.g. {example!r}.")
        skip = {n.lower() for n in TEXT_COLUMNS + TIME_COLUMNS + labels + ROUTE_COLUMNS}
        sensors = [j for j, n in enumerate(names) if j not in roles and n.lower() not in skip]
    if not sensors:
        raise ValueError("No sensor columns: every column is a label, time, distance, run or split column.")
    return Layout(names, tuple(sensors), label_j, time_j, distance_j, run_j, split_j)
