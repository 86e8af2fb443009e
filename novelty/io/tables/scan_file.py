"""Scans from the user's own files (CSV, NPZ or MAT): which column is what, and every cell checked.

A file is a table: one row a scan, one column a sensor or a per-scan value.
A CSV may have a header row (column names) or not (columns are then named
``s0, s1, ...``); an NPZ holds an array ``X`` (its columns named ``s0, s1,
...``) and any 1-D arrays of one value per scan, each a column by its name.

Which columns are what:

- ``columns``: the sensor readings, by name, by ``fnmatch`` pattern
  (``"field.ranges*"``) or by 0-based index in the file, as a list or a
  comma-separated string. Default: every column that is not one of those
  below; a text column among them is refused with a message naming it.
- ``label``: per-scan ground truth, 1 novel, 0 normal, nothing else
  (:mod:`novelty.io.tables.labels`: NaN, scikit-learn's -1/+1 or 0.5 are
  refused, saying where). Default: a column named ``y`` or ``label``; in a
  file of the ``points`` input (:func:`novelty.io.tables.columns.is_points_file`),
  whose ``y`` is the robot's position, a column named ``label`` only.
- ``time``: per-scan timestamps, given to the detector as elapsed time, never
  a sensor. Default: a column named ``time``, ``timestamp``,
  ``field.header.stamp`` or ``%time``. ROS stamps (``%time``, ``*.stamp``)
  are nanoseconds and are converted to seconds.
- ``distance``, ``run``, ``split``: distance along the route (m), traversal
  number, ``train``/``test`` part, by these names.

A cell that cannot be read is refused by where it is: the line of a CSV file
(as an editor numbers it) or the row of an NPZ file (its index in ``X``),
and the column, with what it holds (``scans.csv, line 14, column 'us05':
expected a number, got an empty cell``).

A ``rostopic echo -p`` export (a ``%time`` column, ``field.*`` columns) mixes
header fields with readings; its sensor columns must be chosen
(``columns="field.ranges*"``), so that no timestamp or sequence number is
ever read as a sensor.

The registered task ``files`` (:mod:`novelty.datasets.files`) splits the
scans of one file into a training and a test part.

Reading a file into columns is :mod:`novelty.io.tables.table`, deciding which
column is what :mod:`novelty.io.tables.columns`; their names are importable
from here too.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ...data import Dataset
from .columns import (LABEL_COLUMNS, ROUTE_COLUMNS, TEXT_COLUMNS, TIME_COLUMNS, Layout,  # noqa: F401
                      cell_text, is_ros_export, plan_columns)
from .data_files import is_float
from .labels import check_labels
from .smoothing import smooth_by_distance
from .table import Table, header_of, read_table  # noqa: F401

__all__ = ["Table", "Layout", "read_table", "plan_columns", "read_scans", "sensors_to_scans", "smooth_by_distance",
           "PREPROCESSING"]

#: preprocessing applied to the sensor columns, by name
PREPROCESSING = ("none", "paper")


# ------------------------------------------------------------ scans of a file
def _numbers(table: Table, layout: Layout, j: int) -> np.ndarray:
    """Column ``j`` as numbers; a cell that is not one is refused by its line (or row) and column."""
    values = table.values[j]
    if values.dtype.kind in "US":
        i = next(i for i, cell in enumerate(values) if not is_float(cell))
        raise layout.not_a_number(j, values[i], table.where(i))
    return values


def _finite(table: Table, layout: Layout, j: int) -> np.ndarray:
    """Column ``j`` (a label, time, distance or run) as finite numbers."""
    values = _numbers(table, layout, j)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise ValueError(f"{table.where(bad[0])}, {layout.column(j)}: expected a finite number, "
                         f"got {float(values[bad[0]])}.")
    return values


def _check_preprocess(preprocess) -> str:
    choice = "none" if preprocess is None else preprocess
    if choice not in PREPROCESSING:
        raise ValueError(f"preprocess must be one of {', '.join(PREPROCESSING)}; got {preprocess!r}.")
    return choice


def sensors_to_scans(X: np.ndarray, preprocess=None, threshold: float | None = None,
                     where: Callable[[int, int], str] | None = None) -> np.ndarray:
    """The detector's input from raw sensor values: checked, and preprocessed if asked.

    ``where(i, k)`` says where reading ``X[i, k]`` came from (a file, its line
    and column), for the message refusing it.
    """
    paper = _check_preprocess(preprocess) == "paper"
    # the paper's preprocessing reads inf as no echo; NaN is never a reading
    bad = np.isnan(X) if paper else ~np.isfinite(X)
    if bad.any():
        i, k = np.argwhere(bad)[0]
        value = float(X[i, k])
        expected = "a range in metres (inf for no echo)" if paper else "a finite number"
        hint = " (preprocess='paper' reads inf as no echo)" if np.isinf(value) else ""
        place = where(i, k) if where is not None else f"scan {i}, sensor {k}"
        raise ValueError(f"{place}: expected {expected}, got {value}{hint}.")
    if paper:
        # imported here: novelty.sonar loads the whole simulator, which every start of the
        # command line would otherwise pay
        from ...sonar.preprocessing import PAPER_THRESHOLD, preprocess as paper_preprocess

        X = paper_preprocess(X, PAPER_THRESHOLD if threshold is None else threshold)
    return X


def read_scans(path, columns=None, label=None, time=None, preprocess=None,
               threshold: float | None = None, bin_length: float | None = None,
               split=None) -> Dataset:
    """The scans of a CSV or NPZ file as a :class:`~novelty.datasets.Dataset`.

    Parameters
    ----------
    path : str or Path
        A ``.csv`` (header optional) or ``.npz`` (array ``X``) file.
    columns : str, int or list, optional
        Sensor columns: names, ``fnmatch`` patterns or 0-based indices (a
        comma-separated string or a list). Default: every column without
        another role.
    label, time : str or int, optional
        The label column (non-zero = novel) and the time column (timestamps,
        never a sensor). Defaults: see the module docstring.
    preprocess : {None, "none", "paper"}
        ``"paper"``: ranges in metres become ``1 - min(r, threshold) / threshold``
        (Marsland et al., 2000, section 4.1; :func:`novelty.sonar.preprocess`).
    threshold : float, optional
        The range (m) mapped to 0 by the paper's preprocessing (default: the
        paper's 4 m, :data:`novelty.sonar.preprocessing.PAPER_THRESHOLD`).
    bin_length : float, optional
        Average consecutive scans over each ``bin_length`` metres of travel
        (the paper's 10 cm smoothing, section 4.2); needs a ``distance`` column.
    split : str or int, optional
        A column of ``train``/``test`` values (default: a column named ``split``).

    Returns
    -------
    Dataset
        ``X``, and ``y``, ``distance``, ``run``, ``split`` where the file has
        them; ``columns["time"]`` the timestamps in seconds, if any.
    """
    table = read_table(path)
    layout = plan_columns(table.names, columns, label, time, split)
    raw = np.column_stack([_numbers(table, layout, j) for j in layout.sensors])
    X = sensors_to_scans(raw, preprocess, threshold,
                         lambda i, k: f"{table.where(i)}, {layout.column(layout.sensors[k])}")
    fields: dict = {}
    if layout.label is not None:
        fields["y"] = check_labels(_finite(table, layout, layout.label),
                                   lambda i: f"{table.where(i)}, {layout.column(layout.label)}")
    if layout.distance is not None:
        fields["distance"] = _finite(table, layout, layout.distance)
    if layout.run is not None:
        fields["run"] = _finite(table, layout, layout.run).astype(np.int64)
    if layout.split is not None:
        fields["split"] = _split_values(table, layout)
    columns_ = {}
    if layout.time is not None:
        columns_["time"] = _finite(table, layout, layout.time) * layout.time_scale
    data = Dataset(Path(path).stem, X, columns=columns_, metadata={
        "source": str(path), "sensor_columns": layout.sensor_names,
        "time_column": None if layout.time is None else layout.names[layout.time],
        "preprocess": _check_preprocess(preprocess)}, **fields)
    return data if bin_length is None else smooth_by_distance(data, bin_length)


def _split_values(table: Table, layout: Layout) -> np.ndarray:
    values = table.values[layout.split]
    parts = np.char.lower(np.char.strip(values.astype(str)))
    wrong = np.flatnonzero(~np.isin(parts, ["train", "test"]))
    if wrong.size:
        i = wrong[0]
        raise ValueError(f"{table.where(i)}, {layout.column(layout.split)}: expected 'train' or 'test', "
                         f"got {cell_text(values[i])}.")
    return parts
