"""The registered task ``files``: the user's own scans (CSV, NPZ or MAT), learned in one part, scored in another.

The file is read by :func:`novelty.io.tables.scan_file.read_scans` (which
column is what, every cell checked: :mod:`novelty.io.tables.scan_file`),
whose names are importable from here too.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..data import Dataset
from ..io.tables.labels import check_both_classes
from ..io.tables.scan_file import (PREPROCESSING, Layout, Table, plan_columns, read_scans,  # noqa: F401
                                   read_table, sensors_to_scans, smooth_by_distance)
from .resampling import Resampling

__all__ = ["files", "Table", "Layout", "read_table", "plan_columns", "read_scans", "smooth_by_distance",
           "PREPROCESSING"]


def files(path, test_path=None, columns=None, label=None, time=None, split=None, train_rows=None,
          preprocess=None, threshold=None, bin_length=None, train_passes: int = 1, resample=None, test=None,
          min_rows=None, max_rows=None, scale=None, training=None, seed: int = 0):
    """Task: the user's own scans (CSV, NPZ or MAT), learned in a training part, scored in a test part.

    The training and test parts come from one of (exactly one may be given;
    without any, a column named ``split`` is used):

    - ``test_path``: a second file of the same columns, the test part;
    - ``split``: a column of ``train``/``test`` values;
    - ``train_rows``: the first rows learned, the rest tested, in file order
      and never shuffled (a file stored with its anomalies last is then a
      different experiment); an int (a count) or a float in (0, 1) (a
      fraction of the rows);
    - ``resample``: a split drawn for each ``seed``, ``stratified`` or
      ``shuffled``, of ``test`` (default 0.3) tested, the table first
      bootstrapped to ``min_rows`` or subsampled to ``max_rows``
      (:mod:`novelty.datasets.resampling`).

    Whichever the split, ``training="clean"`` drops the novel scans from the
    training part (default ``"contaminated"``: they stay, unlabelled) and
    ``scale`` (``"minmax"``, ``"standard"``) is fitted on the training part.
    The task's ``metadata["split_description"]`` says all of it in one line.

    The test part needs labels (``label``, or a ``y``/``label`` column): 1
    novel, 0 normal, with both classes present. Column choice, timestamps
    and preprocessing: see :func:`read_scans`.

    Parameters
    ----------
    path : str or Path
        The scans (all of them, or the training part with ``test_path``).
    test_path : str or Path, optional
    columns, label, time, split, preprocess, threshold, bin_length
        As in :func:`read_scans`.
    train_rows : int or float, optional
    train_passes : int, default=1
        How many times a detector streams the training part.
    resample, test, min_rows, max_rows, scale, training
        The resampling protocol (:class:`~novelty.datasets.resampling.Resampling`).
    seed : int, default=0
        The seed of a drawn split (unused otherwise).
    """
    if isinstance(train_passes, bool) or not isinstance(train_passes, int) or train_passes < 1:
        raise ValueError(f"train_passes must be a positive int; got {train_passes!r}.")
    protocol = Resampling(resample, test, min_rows, max_rows, scale, training).check()
    given = [k for k, v in (("test_path", test_path), ("split", split), ("train_rows", train_rows),
                            ("resample", resample)) if v is not None]
    if len(given) > 1:
        raise ValueError(f"Give one way to split the scans into training and test; got {' and '.join(given)}.")
    options = dict(columns=columns, label=label, time=time, preprocess=preprocess, threshold=threshold,
                   bin_length=bin_length)
    if test_path is not None:
        data = _joined(read_scans(path, **options), read_scans(test_path, **options))
        how = f"trained on {Path(path).name}, tested on {Path(test_path).name}"
    else:
        data = read_scans(path, split=split if not protocol.draws else None, **options)
        if train_rows is not None:
            data = replace(data, split=_split_by_rows(len(data), train_rows))
            n_train = int((data.split == "train").sum())
            how = (f"the first {n_train} of {len(data)} rows in file order trained (not shuffled), "
                   "the rest tested")
        elif protocol.draws:
            how = ""
        elif data.split is None:
            raise ValueError(f"{path}: how are the scans split into training and test? Give train_rows, "
                             "split (a column of train/test values), test_path, or resample=stratified.")
        else:
            how = "split by the file's train/test column"
    if data.y is None:
        raise ValueError(f"{path}: the test scans need labels; name the label column with label= (--label).")
    data = protocol.apply(data, seed)
    test_part = data.split == "test"
    if not test_part.any() or test_part.all():
        raise ValueError(f"{path}: the split leaves no {'test' if not test_part.any() else 'training'} scans.")
    check_both_classes(data.y[test_part], str(path))
    return replace(data, name="files", metadata={
        **data.metadata, "task": "files", "train_passes": train_passes,
        "test_source": str(test_path) if test_path is not None else str(path),
        "split_description": protocol.describe(how),
        "description": f"Learn the training scans of {Path(path).name}, score the test scans."})


def _split_by_rows(n: int, train_rows) -> np.ndarray:
    if isinstance(train_rows, bool) or not isinstance(train_rows, (int, float)):
        raise ValueError(f"train_rows must be a count or a fraction in (0, 1); got {train_rows!r}.")
    if isinstance(train_rows, float):
        if not 0 < train_rows < 1:
            raise ValueError(f"train_rows as a fraction must lie in (0, 1); got {train_rows!r}.")
        train_rows = math.floor(train_rows * n)
    if not 0 < train_rows < n:
        raise ValueError(f"train_rows must leave scans on both sides: 1 to {n - 1} of {n}; got {train_rows}.")
    return np.where(np.arange(n) < train_rows, "train", "test")


def _joined(train: Dataset, test: Dataset) -> Dataset:
    if train.n_sensors != test.n_sensors:
        raise ValueError(f"The training file has {train.n_sensors} sensor columns, the test file "
                         f"{test.n_sensors}.")
    both = (train, test)

    def stacked(field: str):
        values = [getattr(d, field) for d in both]
        return None if any(v is None for v in values) else np.concatenate(values)

    columns = {k: np.concatenate([train.columns[k], test.columns[k]])
               for k in train.columns if k in test.columns}
    # the training file needs no labels: what is learned is familiar
    y = None if test.y is None else np.concatenate(
        [np.zeros(len(train), np.int64) if train.y is None else train.y, test.y])
    return Dataset(train.name, np.vstack([train.X, test.X]), y=y, distance=stacked("distance"),
                   run=stacked("run"), columns=columns, metadata=train.metadata,
                   split=np.array(["train"] * len(train) + ["test"] * len(test)))
