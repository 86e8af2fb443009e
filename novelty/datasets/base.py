"""The one dataset type every source of scans returns.

A :class:`Dataset` is a sequence of scans in the order they were perceived,
with whatever ground truth the source knows. A novelty *task* is a dataset
whose scans are split into a ``"train"`` part (familiar: the detector learns
it, ``train_passes`` times, as a robot repeats a route) and a ``"test"`` part
(scored without learning, with per-scan labels ``y``: 1 novel, 0 normal).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

__all__ = ["Dataset"]


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
    metadata : dict
        Anything else (sensor names, units, seed, map name, ``train_passes``).
    """

    name: str
    X: np.ndarray
    y: np.ndarray | None = None
    split: np.ndarray | None = None
    distance: np.ndarray | None = None
    poses: np.ndarray | None = None
    feature_ids: tuple | None = None
    run: np.ndarray | None = None
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
        """Write the scans and ground truth as plain arrays (no pickle)."""
        arrays = {"X": self.X}
        for name in ("y", "distance", "poses", "run"):
            if getattr(self, name) is not None:
                arrays[name] = getattr(self, name)
        if self.split is not None:
            arrays["split"] = self.split.astype("U5")
        with open(path, "wb") as fh:
            np.savez(fh, **arrays)

    def to_csv(self, path) -> None:
        """Write one row per scan: the sensors, then ``y``/``distance`` when known."""
        columns = [self.X]
        header = [f"s{i}" for i in range(self.n_sensors)]
        for name in ("y", "distance"):
            if getattr(self, name) is not None:
                columns.append(np.asarray(getattr(self, name), dtype=np.float64)[:, None])
                header.append(name)
        np.savetxt(path, np.hstack(columns), delimiter=",", header=",".join(header), comments="",
                   fmt="%.10g")
