"""One scan of the ``points`` input as the rays a grid of the world reads: where each echo lies, and the free space before it.

A row of :mod:`novelty.io.scans.points` gives the robot's position ``p`` and each
sector's end point ``e_k`` in the world: its nearest echo when its nearness is
above 0, else as far as its beams saw free space. :func:`scan_rays` turns it
into rays from ``p``:

- a sector ending more than ``max_range`` from ``p`` is cut to ``max_range``
  along its direction and read as no echo (the bound of every scan's cost:
  its rays' cells grow linearly with their length, :mod:`novelty.maps.grid_walk`);
- with a cone width ``a > 0`` (a sonar's cone, or the angle a sector stands
  for: :func:`sector_width`) each sector is read as ``m = 1 + ceil(a L / (c /
  2))`` rays evenly across its cone (``L`` the scan's longest sector, ``c``
  the cell size: their ends at most half a cell apart), each as long as its
  sector: its echo spread over the arc at its range, its free space over the
  cone inside it (Moravec & Elfes 1985); with ``a = 0`` each sector is one
  ray, to its own end point;
- a ray's free stretch runs from ``p`` to ``reach`` along it: its length less
  ``margin`` when it has an echo (the free space stops short of the echo),
  its whole length when it has none.

The function is written once, in plain Python over scalars and arrays: the
references run it as it is and the compiled kernels compile it
(:mod:`novelty.maps.grid_kernels`), so the two read the same rays. The
trigonometric functions are the C library's (``math``) in both.

References
----------
Moravec, H. & Elfes, A. (1985). High resolution maps from wide angle sonar.
Proc. IEEE ICRA, 116-121.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["scan_rays", "ray_count", "sector_width", "cone_rays", "MapRangeWarning"]


class MapRangeWarning(UserWarning):
    """Sectors ending beyond a grid's ``max_range`` were cut to it and read as no echo."""


def sector_width(x, y, ex, ey):
    """The angle one sector of a scan stands for (rad; ours): the median gap between its bearings round the circle.

    ``(x, y)`` the robot's position, ``ex``, ``ey`` the sectors' end points
    (those with no echo included: they lie along their sectors' directions).
    End points at the robot's position have no bearing and are left out; with
    fewer than two left the width is 0 (the axes). At most pi.

    >>> round(math.degrees(sector_width(0.0, 0.0, np.array([1.0, 0.0, -2.0, 0.0]), np.array([0.0, 1.0, 0.0, -1.0]))), 6)
    90.0
    """
    bearings = np.empty(ex.shape[0])
    n = 0
    for k in range(ex.shape[0]):
        dx, dy = ex[k] - x, ey[k] - y
        if dx != 0.0 or dy != 0.0:
            bearings[n] = math.atan2(dy, dx)
            n += 1
    if n < 2:
        return 0.0
    bearing = _sorted_turn(bearings[:n])
    gaps = np.empty(n)
    for k in range(n - 1):
        gaps[k] = bearing[k + 1] - bearing[k]
    gaps[n - 1] = bearing[0] + 2.0 * math.pi - bearing[n - 1]
    gaps = np.sort(gaps)
    median = gaps[n // 2] if n % 2 else (gaps[n // 2 - 1] + gaps[n // 2]) / 2.0
    return min(median, math.pi)


def _sorted_turn(a):
    """``a`` sorted: as it is, or turned at its one descent, when it is the bearings of a scan in order (the
    turn crossing +-pi at most once); else sorted."""
    n = a.shape[0]
    descents, at = 0, 0
    for k in range(n - 1):
        if a[k + 1] < a[k]:
            descents += 1
            at = k + 1
    if descents == 0:
        return a
    if descents == 1 and a[n - 1] <= a[0]:
        return np.concatenate((a[at:], a[:at]))
    return np.sort(a)


def cone_rays(arc, longest, cell_size):
    """The rays a cone of width ``arc`` is read as: ``1 + ceil(arc L / (c / 2))``, 1 without a cone."""
    if arc <= 0.0:
        return 1
    return 1 + math.ceil(arc * longest / (cell_size / 2.0))


def ray_count(x, y, ex, ey, arc, cell_size, max_range):
    """The rays :func:`scan_rays` makes of a scan: ``n`` sectors times each cone's rays."""
    longest = 0.0
    for k in range(ex.shape[0]):
        dx, dy = ex[k] - x, ey[k] - y
        longest = max(longest, min(math.sqrt(dx * dx + dy * dy), max_range))
    width = sector_width(x, y, ex, ey) if arc < 0.0 else arc
    return ex.shape[0] * cone_rays(width, longest, cell_size)


def scan_rays(x, y, near, ex, ey, arc, cell_size, max_range, margin, hit, end_x, end_y, free_x, free_y):
    """The rays of one scan (module docstring) into the output arrays; returns ``(rays, sectors cut)``.

    Parameters
    ----------
    x, y : float
        The robot's position (m).
    near, ex, ey : ndarray of shape (n,)
        The sectors' nearness and end points (m), as a ``points`` row holds them.
    arc : float
        The cone width ``a`` (rad); 0: each sector on its axis. A negative
        value: as wide as the angle a sector stands for (:func:`sector_width`).
    cell_size, max_range, margin : float
        ``c``, the longest a ray may be, and how far short of an echo its free
        stretch stops (m).
    hit, end_x, end_y, free_x, free_y : ndarray
        Receive, ray by ray, whether it ends in an echo, its end point, and
        its free stretch's end (NaN where it has none: ``reach <= 0``). They
        need room for :func:`ray_count` rays.
    """
    n = ex.shape[0]
    length, dx, dy = np.empty(n), np.empty(n), np.empty(n)
    cut = np.zeros(n, dtype=np.bool_)
    longest = 0.0
    for k in range(n):
        dx[k], dy[k] = ex[k] - x, ey[k] - y
        length[k] = math.sqrt(dx[k] * dx[k] + dy[k] * dy[k])
        if length[k] > max_range:   # cut to max_range along its direction: no echo
            scale = max_range / length[k]
            dx[k], dy[k], length[k] = dx[k] * scale, dy[k] * scale, max_range
            cut[k] = True
        longest = max(longest, length[k])
    width = sector_width(x, y, ex, ey) if arc < 0.0 else arc
    m = cone_rays(width, longest, cell_size)
    r = 0
    for k in range(n):
        echo = near[k] > 0.0 and not cut[k]
        if m == 1:
            end_x[r], end_y[r] = (x + dx[k], y + dy[k]) if cut[k] else (ex[k], ey[k])
            ux, uy = (dx[k] / length[k], dy[k] / length[k]) if length[k] > 0.0 else (0.0, 0.0)
            _free(x, y, ux, uy, length[k], echo, margin, r, hit, free_x, free_y)
            r += 1
            continue
        axis = math.atan2(dy[k], dx[k])
        for q in range(m):   # evenly across the cone, its last ray on its edge exactly
            angle = axis + (width / 2.0 if q == m - 1 else -width / 2.0 + q * (width / (m - 1)))
            ux, uy = math.cos(angle), math.sin(angle)
            end_x[r], end_y[r] = x + length[k] * ux, y + length[k] * uy
            _free(x, y, ux, uy, length[k], echo, margin, r, hit, free_x, free_y)
            r += 1
    return r, int(cut.sum())


def _free(x, y, ux, uy, length, echo, margin, r, hit, free_x, free_y):
    """Ray ``r``'s echo flag and the end of its free stretch (NaN: none)."""
    hit[r] = echo
    reach = length - margin if echo else length
    if reach > 0.0:
        free_x[r], free_y[r] = x + reach * ux, y + reach * uy
    else:
        free_x[r], free_y[r] = math.nan, math.nan
