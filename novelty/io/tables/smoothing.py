"""The paper's smoothing of scans over travel (:func:`smooth_by_distance`), used by :mod:`novelty.datasets.files`."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...data import Dataset

__all__ = ["smooth_by_distance"]


def smooth_by_distance(data: Dataset, bin_length: float) -> Dataset:
    """Average consecutive scans over each ``bin_length`` metres of travel.

    The paper's smoothing (Marsland et al., 2000, section 4.2): "approximately
    every 10 cm along the route the smoothed values of the sonar perceptions
    over that 10 cm of travel were presented". Consecutive scans with the same
    ``floor(distance / bin_length)`` (and the same run and split) become one:
    the mean of their scans and distances, the last timestamp (the moment it
    is presented), novel if any of them is.
    """
    if isinstance(bin_length, bool) or not isinstance(bin_length, (int, float)) or not bin_length > 0:
        raise ValueError(f"bin_length must be a positive number of metres; got {bin_length!r}.")
    if data.distance is None:
        raise ValueError("Smoothing over travel (bin_length) needs a 'distance' column.")
    keys = [np.floor(data.distance / bin_length + 1e-9)]
    keys += [k for k in (data.run, data.split) if k is not None]
    change = np.zeros(len(data), dtype=bool)
    change[0] = True
    for k in keys:
        change[1:] |= k[1:] != k[:-1]
    starts = np.flatnonzero(change)
    counts = np.diff(np.append(starts, len(data)))
    mean = lambda a: np.add.reduceat(a, starts, axis=0) / counts.reshape((-1,) + (1,) * (a.ndim - 1))  # noqa: E731
    last = starts + counts - 1
    return replace(
        data,
        X=mean(data.X),
        distance=mean(data.distance),
        y=None if data.y is None else np.maximum.reduceat(data.y, starts),
        run=None if data.run is None else data.run[starts],
        split=None if data.split is None else data.split[starts],
        poses=None, feature_ids=None,
        columns={name: v[last] for name, v in data.columns.items()},
        metadata={**data.metadata, "bin_length_m": float(bin_length)},
    )
