"""The one dataset type every source of scans returns.

Its own module, below :mod:`novelty.tasks` (which builds datasets and
tasks), :mod:`novelty.datasets` (which makes them by name), the readers of
:mod:`novelty.io` and :mod:`novelty.sonar` (whose simulator returns them),
so that none of those imports another to reach it; a name beside
``datasets`` that keeps its place because a benchmark's definition digests
name the type by its module.

A :class:`Dataset` is a sequence of scans in the order they were perceived,
with whatever ground truth the source knows. A novelty *task* is a dataset
whose scans are split into a ``"train"`` part (familiar: the detector learns
it, ``train_passes`` times, as a robot repeats a route) and a ``"test"`` part
(scored without learning, with per-scan labels ``y``: 1 novel, 0 normal).
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

__all__ = ["Dataset", "FAMILIAR"]

#: The tracked-feature label (an exploration task's ``feature`` column) of a scan that
#: perceives no tracked feature: a familiar scan.
FAMILIAR = ""


@dataclass(frozen=True, eq=False)
class Dataset:
    """Scans with optional ground truth.

    Attributes
    ----------
    name : str
        Registry name (or file name) the data came from.
    X : ndarray of shape (n_scans, n_sensors)
        The scans, in order.
    y : ndarray of shape (n_scans,) or None
        Per-scan novelty labels (1 novel, 0 normal) where a task defines them.
    split : ndarray of shape (n_scans,) of str, or None
        ``"train"`` or ``"test"`` per scan, for tasks.
    distance : ndarray of shape (n_scans,) or None
        Distance along the route (m) at each scan.
    poses : ndarray of shape (n_scans, 3) or None
        Robot pose (x, y, heading in radians) at each scan.
    feature_ids : tuple of frozenset or None
        Ids of the map features perceived in each scan (any sonar).
    run : ndarray of shape (n_scans,) of int, or None
        Which traversal each scan belongs to.
    columns : dict of str to ndarray
        Further per-scan values (e.g. the class of each scan of a labelled
        real data set); each has one row per scan and follows :meth:`subset`.
    metadata : dict
        Anything else, about the data as a whole (sensor names, units, seed,
        map name, ``train_passes``).
    """

    name: str
    X: np.ndarray
    y: np.ndarray | None = None
    split: np.ndarray | None = None
    distance: np.ndarray | None = None
    poses: np.ndarray | None = None
    feature_ids: tuple | None = None
    run: np.ndarray | None = None
    columns: dict[str, np.ndarray] = field(default_factory=dict)
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        X = np.asarray(self.X, dtype=np.float64)
        if X.ndim != 2:
            raise ValueError(f"Dataset.X must be 2-D (n_scans, n_sensors); got shape {X.shape}.")
        object.__setattr__(self, "X", X)
        n = X.shape[0]
        for name in ("y", "split", "distance", "poses", "run"):
            value = getattr(self, name)
            if value is not None:
                value = np.asarray(value)
                if value.shape[0] != n:
                    raise ValueError(f"Dataset.{name} has {value.shape[0]} rows; X has {n}.")
                object.__setattr__(self, name, value)
        if self.feature_ids is not None and len(self.feature_ids) != n:
            raise ValueError(f"Dataset.feature_ids has {len(self.feature_ids)} entries; X has {n}.")
        columns = {}
        for name, value in self.columns.items():
            value = np.asarray(value)
            if value.shape[:1] != (n,):
                raise ValueError(f"Dataset column {name!r} has {value.shape[:1]} rows; X has {n}.")
            columns[name] = value
        object.__setattr__(self, "columns", columns)

    def __len__(self) -> int:
        return self.X.shape[0]

    @property
    def n_sensors(self) -> int:
        return self.X.shape[1]

    def subset(self, mask_or_index) -> "Dataset":
        """The scans selected by a boolean mask or an index array."""
        idx = np.asarray(mask_or_index)
        if idx.dtype == bool:
            idx = np.flatnonzero(idx)
        take = lambda a: None if a is None else a[idx]  # noqa: E731
        return replace(
            self,
            X=self.X[idx],
            y=take(self.y),
            split=take(self.split),
            distance=take(self.distance),
            poses=take(self.poses),
            run=take(self.run),
            feature_ids=None if self.feature_ids is None else tuple(self.feature_ids[i] for i in idx),
            columns={name: value[idx] for name, value in self.columns.items()},
        )

    def _part(self, which: str) -> "Dataset":
        if self.split is None:
            raise ValueError(f"Dataset {self.name!r} has no train/test split; it is not a task.")
        return self.subset(self.split == which)

    def train(self) -> "Dataset":
        """The familiar scans a detector learns from (a task's training part)."""
        return self._part("train")

    def test(self) -> "Dataset":
        """The scans a detector scores without learning (a task's test part)."""
        return self._part("test")

    @property
    def train_passes(self) -> int:
        """How many times a detector streams the training part (default 1)."""
        return int(self.metadata.get("train_passes", 1))

    def to_npz(self, path) -> None:
        """Write the scans and all ground truth as plain arrays (no pickle).

        ``feature_ids`` and ``metadata`` are stored as JSON text, the split
        and string columns as unicode arrays, so ``numpy.load`` reads the file
        with ``allow_pickle=False``.
        """
        arrays: dict[str, np.ndarray] = {"X": self.X}
        for name in ("y", "distance", "poses", "run"):
            if getattr(self, name) is not None:
                arrays[name] = getattr(self, name)
        if self.split is not None:
            arrays["split"] = self.split.astype("U5")
        for name, value in self.columns.items():
            arrays[f"column_{name}"] = value.astype(str) if value.dtype == object else value
        if self.feature_ids is not None:
            arrays["feature_ids"] = np.array(json.dumps([sorted(map(str, f)) for f in self.feature_ids]))
        arrays["metadata"] = np.array(json.dumps(self.metadata, default=_jsonable))
        with open(path, "wb") as fh:
            np.savez(fh, **arrays)

    def to_csv(self, path) -> None:
        """Write one row per scan: the sensors, then the per-scan ground truth.

        Columns ``s0..s{n-1}``, then those known of ``y``, ``distance``,
        ``run``, ``split``, the extra columns, and ``features`` (feature ids
        joined by ``;``).
        """
        header = [f"s{i}" for i in range(self.n_sensors)]
        extra: list[tuple[str, Any]] = []
        for name in ("y", "distance", "run", "split"):
            if getattr(self, name) is not None:
                extra.append((name, getattr(self, name)))
        extra += list(self.columns.items())
        if self.feature_ids is not None:
            extra.append(("features", [";".join(sorted(map(str, f))) for f in self.feature_ids]))
        header += [name for name, _ in extra]
        with open(path, "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow(header)
            for i in range(len(self)):
                row = [f"{v:.10g}" for v in self.X[i]]
                row += [_cell(values[i]) for _, values in extra]
                writer.writerow(row)


def _cell(value: Any) -> str:
    if isinstance(value, (float, np.floating)):
        return f"{value:.10g}"
    return str(value.item() if isinstance(value, np.generic) else value)


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (set, frozenset, tuple)):
        return list(value)
    return str(value)
