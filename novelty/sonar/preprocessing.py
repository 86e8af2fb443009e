"""The paper's sonar preprocessing: threshold, normalise, invert, average over travel.

Marsland et al. (2000, section 4.1): "The input vector to the novelty
filter consisted of the 16 sonar sensors, each normalised to be between 0
and 1 and thresholded at about 4 metres. The readings were inverted so that
inputs from sonar responses received from closer objects were greater." and
(section 4.2) "Approximately every 10 cm along the route the smoothed values
of the sonar perceptions over that 10 cm of travel were presented".

So a range ``r`` becomes ``1 - min(r, threshold) / threshold`` (1 at contact,
0 at or beyond the threshold, including "no echo"), and the values of all
sonar rings fired during each 10 cm of travel are averaged.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, sections 4.1-4.2.
"""

from __future__ import annotations

import numpy as np

__all__ = ["preprocess", "bin_by_distance", "PAPER_THRESHOLD", "PAPER_BIN_LENGTH"]

#: Readings at or beyond this range (m) carry no information (Marsland et al., 2000).
PAPER_THRESHOLD = 4.0
#: Travel (m) over which readings are averaged into one perception.
PAPER_BIN_LENGTH = 0.1


def preprocess(ranges, threshold: float = PAPER_THRESHOLD) -> np.ndarray:
    """Threshold, normalise and invert ranges: ``1 - min(r, threshold) / threshold``.

    Parameters
    ----------
    ranges : array-like
        Ranges in metres (any shape); ``inf`` or NaN-free values only.
    threshold : float, default=4.0
        Range (m) mapped to 0.

    Returns
    -------
    ndarray of the same shape, in [0, 1]; closer is larger.

    Examples
    --------
    >>> preprocess([0.0, 1.0, 2.0, 4.0, 6.5]).tolist()
    [1.0, 0.75, 0.5, 0.0, 0.0]
    """
    if not threshold > 0:
        raise ValueError(f"threshold must be positive; got {threshold!r}.")
    r = np.asarray(ranges, dtype=np.float64)
    if np.isnan(r).any():
        raise ValueError("ranges contain NaN.")
    return 1.0 - np.clip(r, 0.0, threshold) / threshold


def bin_by_distance(values, travelled, bin_length: float = PAPER_BIN_LENGTH,
                    n_bins: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Average the rows of ``values`` over each ``bin_length`` of travel.

    Row ``i`` falls in bin ``floor(travelled[i] / bin_length)``. A bin that no
    row falls in (a robot faster than one ring per bin) takes the row
    nearest its centre, so every bin yields a perception.

    Parameters
    ----------
    values : array-like of shape (n, m)
        Per-ring values (already preprocessed).
    travelled : array-like of shape (n,)
        Distance travelled (m) when each row was taken, non-decreasing.
    bin_length : float, default=0.1
    n_bins : int, optional
        Number of bins (default: enough to hold the last row).

    Returns
    -------
    means : ndarray of shape (n_bins, m)
    membership : ndarray of shape (n,) of int
        The bin of each row (-1 beyond ``n_bins``).

    Examples
    --------
    >>> means, bins = bin_by_distance([[1.0], [0.0], [0.5]], [0.02, 0.07, 0.15])
    >>> means.ravel().tolist(), bins.tolist()
    ([0.5, 0.5], [0, 0, 1])
    """
    v = np.asarray(values, dtype=np.float64)
    d = np.asarray(travelled, dtype=np.float64)
    if v.ndim != 2 or d.shape != (v.shape[0],):
        raise ValueError("values must be (n, m) and travelled (n,).")
    if v.shape[0] == 0:
        raise ValueError("No rows to bin.")
    if np.any(np.diff(d) < 0):
        raise ValueError("travelled must be non-decreasing.")
    bins = np.floor(d / bin_length + 1e-9).astype(np.intp)
    if n_bins is None:
        n_bins = int(bins.max()) + 1
    bins = np.where(bins < n_bins, bins, -1)
    sums = np.zeros((n_bins, v.shape[1]))
    counts = np.zeros(n_bins)
    ok = bins >= 0
    np.add.at(sums, bins[ok], v[ok])
    np.add.at(counts, bins[ok], 1.0)
    means = np.empty_like(sums)
    filled = counts > 0
    means[filled] = sums[filled] / counts[filled, None]
    for k in np.flatnonzero(~filled):
        centre = (k + 0.5) * bin_length
        means[k] = v[int(np.argmin(np.abs(d - centre)))]
    return means, bins
