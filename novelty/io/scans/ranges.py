"""Invalid readings by the ROS conventions: what a range, ``+inf``, ``-inf`` and NaN mean.

:func:`clean_ranges` makes the meanings of ``sensor_msgs/LaserScan``,
``sensor_msgs/Range`` and REP 117 explicit before anything reduces a scan:
``+inf`` means no object within range (kept: the paper's "no echo",
preprocessed to 0); ``-inf`` a detection too close to measure (becomes
``range_min``, the closest the sensor tells); NaN an erroneous measurement,
and a finite value outside [``range_min``, ``range_max``] one to discard
(both become NaN: no information).

References
----------
ROS Enhancement Proposal 117, "Informational Distance Measurements"
(Bohren, 2012): the meanings of ``-inf``, ``+inf`` and NaN.
ROS ``sensor_msgs/LaserScan`` and ``sensor_msgs/Range`` message definitions:
"values < range_min or > range_max should be discarded".
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["clean_ranges"]


def clean_ranges(ranges, range_min: float = 0.0, range_max: float = math.inf) -> np.ndarray:
    """Ranges with REP 117's meanings made explicit: a range, ``+inf`` (nothing seen) or NaN (no information).

    ``-inf`` (too close to measure) becomes ``range_min``; a finite value
    below ``range_min`` or above ``range_max``, and NaN, become NaN.

    Examples
    --------
    >>> clean_ranges([1.0, float("inf"), float("-inf"), float("nan"), 0.01, 9.0], 0.1, 8.0).tolist()
    [1.0, inf, 0.1, nan, nan, nan]
    """
    r = np.array(ranges, dtype=np.float64)
    # NaN compares False (and stays NaN); only the few beams outside the range are looked at again
    low, high = r < range_min, r > range_max
    # (count_nonzero: ndarray.any's wrapper costs more than the scan's comparison)
    if np.count_nonzero(low):
        r[low] = np.where(r[low] == -np.inf, range_min, np.nan)
    if np.count_nonzero(high):
        high &= r != np.inf
        r[high] = np.nan
    return r
