"""What every scan of a bag goes through, compiled: its ranges cleaned, and its ring from offset origins.

- :func:`clean_into`: a scan's ranges with REP 117's meanings made
  explicit, in one pass, as :func:`novelty.io.scans.ranges.clean_ranges` (the
  readable reference, used for CARMEN logs and the transformers) makes
  them; the tests compare the two.
- :func:`offset_nearest`: each sector's nearest range seen from the robot's
  centre, of beams from offset origins.

:meth:`novelty.io.scans.sweep_rings.RingMaker` calls :func:`offset_nearest` for a
sweep whose sensor is off the centre and whose ring is each sector's
nearest range (the paper's): one pass over the beams, each end point's
distance ``hypot`` from the centre and, for a beam close enough to its
sensor to leave its direction's sector and not plainly inside it, its
bearing ``atan2`` placed as
:func:`novelty.io.scans.sectors.sector_index` places an angle. The numpy path of
:func:`novelty.io.scans.sweep_rings.reference_ring` computes the same ring for
every beam; the tests compare the two. Imported only where a sweep needs
them: numba's import and the kernels' first compilation (cached on disk
after) cost about a second, which reading a CARMEN log never pays.
"""

from __future__ import annotations

import math

from numba import njit

from .sectors import SNAP

__all__ = ["clean_into", "offset_nearest"]

_TURN = 2 * math.pi


@njit(cache=True, error_model="numpy")
def clean_into(ranges, range_min, range_max, out):
    """``out`` (float64) the ranges cleaned: ``-inf`` to ``range_min``; a finite value outside
    [``range_min``, ``range_max``] to NaN; NaN and ``+inf`` as they are."""
    for i in range(ranges.shape[0]):
        r = float(ranges[i])
        if r < range_min:
            out[i] = range_min if r == -math.inf else math.nan
        elif r > range_max and r != math.inf:
            out[i] = math.nan
        else:
            out[i] = r


@njit(cache=True, error_model="numpy")
def offset_nearest(ranges, origins, cos, sin, index, safe, bounds, low, high, n_sectors, front, ring):
    """Fill ``ring`` (n_sectors) with each sector's nearest end point's distance, ``+inf`` where none.

    ``bounds[k]`` is the unit vector of sector ``k``'s first direction
    (``bounds[n_sectors]`` the last one's end): an end point at least 1e-5
    rad inside its direction's sector by both (two cross products) is
    there, as its bearing would say; any other has its bearing computed.
    """
    full = high - low >= _TURN - 1e-12
    narrow = (high - low) / n_sectors < math.pi   # the cross products tell inside from outside
    for k in range(n_sectors):
        ring[k] = math.inf
    for i in range(ranges.shape[0]):
        r = ranges[i]
        if r != r:   # NaN: no information
            continue
        k = index[i]
        if r == math.inf:
            d = math.inf   # nothing seen along the beam's own direction
        else:
            x = origins[i, 0] + r * cos[i]
            y = origins[i, 1] + r * sin[i]
            d = math.sqrt(x * x + y * y)
            if r < safe[i] and not (narrow and k >= 0
                                    and bounds[k, 0] * y - bounds[k, 1] * x > 1e-5 * d
                                    and x * bounds[k + 1, 1] - y * bounds[k + 1, 0] > 1e-5 * d):
                a = low + (math.atan2(y, x) - front - low) % _TURN
                if full and a >= high - SNAP:
                    a = low
                k = int(math.floor((a - low + SNAP) / (high - low) * n_sectors))
                if abs(a - high) <= 1e-8 + 1e-5 * abs(high):
                    k = n_sectors - 1
                if a < low - 1e-12 or a > high + 1e-12 or k < 0 or k >= n_sectors:
                    k = -1
        if k >= 0 and d < ring[k]:
            ring[k] = d
