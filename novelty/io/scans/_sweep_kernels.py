"""What every scan of a bag goes through, compiled: its ranges cleaned, and its ring from offset origins.

- :func:`clean_into`: a scan's ranges with REP 117's meanings made
  explicit, in one pass, as :func:`novelty.io.scans.ranges.clean_ranges` (the
  readable reference, used for CARMEN logs and the transformers) makes
  them; the tests compare the two.
- :func:`offset_nearest`: each sector's nearest range seen from the robot's
  centre, of beams from offset origins;
- :func:`world_ends`: each sector's end point of the ``points`` input in the
  world frame, for many sweeps of one geometry, as
  :meth:`novelty.io.scans.points.PointsMaker.rows` needs them: the same
  operations as the numpy reference (``_Beams.ends``, then the pose's
  rotation and translation), element by element, so the two agree bit for
  bit (``hypot`` is the C library's in both); the tests compare them.

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

__all__ = ["clean_into", "offset_nearest", "world_ends"]

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


@njit(cache=True, error_model="numpy")
def world_ends(ranges, origins, unit, order, starts, middle, threshold, pose, out_x, out_y):
    """Each sector's end point in the world frame, one row a sweep, into ``out_x`` and ``out_y`` (m, n_sectors).

    A sweep's beams ``ranges[r]`` start at ``origins[r]`` (``origins[0]`` for all when it holds one) along
    ``unit``; sector ``k``'s beams are ``order[starts[k]:starts[k + 1]]``, its middle beam ``middle[k]``.
    Its end point is that of its first beam at the least distance from the centre, within ``threshold``,
    else ``threshold`` along that beam (along its middle beam where no beam returned); then
    ``x + c e_x - s e_y``, ``y + s e_x + c e_y`` with ``pose[r] = (x, y, c, s)``.
    """
    n = starts.shape[0]
    for r in range(ranges.shape[0]):
        o = origins[r if origins.shape[0] > 1 else 0]
        x, y, c, s = pose[r, 0], pose[r, 1], pose[r, 2], pose[r, 3]
        for k in range(n):
            stop = starts[k + 1] if k + 1 < n else order.shape[0]
            least, j, lost = math.inf, -1, False
            for q in range(starts[k], stop):
                i = order[q]
                rr = ranges[r, i]
                if not math.isfinite(rr):
                    continue
                d = math.hypot(o[i, 0] + rr * unit[i, 0], o[i, 1] + rr * unit[i, 1])
                if d != d:
                    lost = True   # NaN: the least is NaN, as numpy's minimum says
                elif d < least:
                    least, j = d, i
            if lost or j < 0:
                j = middle[k]
            rj = ranges[r, j]
            echo = math.isfinite(rj)
            ex, ey = o[j, 0] + (rj if echo else 0.0) * unit[j, 0], o[j, 1] + (rj if echo else 0.0) * unit[j, 1]
            d = math.hypot(ex, ey) if echo else math.inf
            if not d <= threshold:
                dx, dy = (ex, ey) if echo else (unit[j, 0], unit[j, 1])
                h = math.hypot(dx, dy)
                ex, ey = threshold * dx / h, threshold * dy / h
            out_x[r, k] = x + c * ex - s * ey
            out_y[r, k] = y + s * ex + c * ey
