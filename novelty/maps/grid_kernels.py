"""What every compiled grid of the world shares (the habituating map and the occupancy-grid baseline): the grid walk, a scan's rays, and its tiles found by hash.

Plain numba over arrays, as the project's other kernels; imported only where
a compiled map or grid needs it (numba's import and the first compilation,
cached on disk after, cost about a second).

- :func:`walk` and :func:`length`: :func:`~novelty.maps.grid_walk.walk_into`
  and :func:`~novelty.maps.grid_walk.walk_length` compiled as they are;
- :func:`rays` and :func:`ray_count`: :func:`~novelty.maps.scan_rays.scan_rays`
  and :func:`~novelty.maps.scan_rays.ray_count` compiled as they are;
- the tiles (:mod:`novelty.maps.tiles`): a table of ``2**bits`` slots
  (``bits`` such that it is at most half full), each -1 or the order of a
  tile, placed by Knuth's multiplicative hash of its key with linear probing:
  :func:`table_of` builds it from the tiles' keys, :func:`find` and
  :func:`add` look up and insert, :func:`unit` gives a cell's unit by
  equation (1) of :mod:`novelty.maps.tiles` (:func:`unit_in` when its tile's
  order is known: the cells of a ray or of a neighbourhood mostly share a
  tile, whose order a loop looks up once).
"""

from __future__ import annotations

import warnings

import numpy as np
from numba import njit

from .._jit import compiled
from .grid_walk import walk_into, walk_length
from . import scan_rays as _scan
from .tiles import TILE_CELLS, TILE_SHIFT

__all__ = ["walk", "length", "rays", "ray_count", "sector_width", "cone_rays", "table_of", "find", "add", "unit", "unit_in", "tile_key", "bits_for",
           "tiles_crossed", "scan_sizes", "scan_bounds", "check_costs"]

#: the cells of one ray into ``out[:n]``, in order; returns n (``walk_into`` compiled)
walk = compiled(walk_into)
#: equation (2) of :mod:`novelty.maps.grid_walk`: the cells a ray passes through
length = compiled(walk_length)
#: the angle a sector of a scan stands for, and the rays a cone is read as (``sector_width``, ``cone_rays``)
sector_width = compiled(_scan.sector_width, _sorted_turn=compiled(_scan._sorted_turn))
cone_rays = compiled(_scan.cone_rays)
_free = compiled(_scan._free)
#: one scan's rays (``scan_rays`` compiled)
rays = compiled(_scan.scan_rays, sector_width=sector_width, cone_rays=cone_rays, _free=_free)
ray_count = compiled(_scan.ray_count, sector_width=sector_width, cone_rays=cone_rays)

_MASK = (1 << TILE_SHIFT) - 1
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)   # 2**64 / the golden ratio: Knuth's multiplier


def bits_for(capacity: int) -> int:
    """The table's size as a power of two, at least twice ``capacity`` tiles (and 16 slots)."""
    bits = 4
    while (1 << bits) < 2 * capacity:
        bits += 1
    return bits


@njit(cache=True, error_model="numpy", inline="always")
def tile_key(i, j):
    """The key of the tile of cell (i, j) (:func:`novelty.maps.tiles.tile_keys`)."""
    return (((i >> TILE_SHIFT) + (1 << 30)) << 32) + ((j >> TILE_SHIFT) + (1 << 31))


@njit(cache=True, error_model="numpy", inline="always")
def _slot(key, bits):
    return np.int64((np.uint64(key) * _GOLDEN) >> np.uint64(64 - bits))


@njit(cache=True, error_model="numpy")
def find(table, bits, tiles, key):
    """The order of the tile of ``key``, -1 when it is not held."""
    mask = table.shape[0] - 1
    slot = _slot(key, bits)
    while True:
        t = table[slot]
        if t < 0:
            return -1
        if tiles[t] == key:
            return t
        slot = (slot + 1) & mask


@njit(cache=True, error_model="numpy")
def add(table, bits, tiles, n, key):
    """Hold a tile of ``key`` (not held yet) as the ``n``-th: ``tiles[n] = key`` and its slot."""
    mask = table.shape[0] - 1
    slot = _slot(key, bits)
    while table[slot] >= 0:
        slot = (slot + 1) & mask
    table[slot] = n
    tiles[n] = key


@njit(cache=True, error_model="numpy")
def table_of(tiles, n, bits):
    """The table of the first ``n`` tiles' keys, in ``2**bits`` slots."""
    table = np.full(1 << bits, -1, dtype=np.int64)
    for t in range(n):
        add(table, bits, tiles, t, tiles[t])
    return table


@njit(cache=True, error_model="numpy", inline="always")
def unit_in(t, i, j):
    """The unit of cell (i, j) in the tile held ``t``-th, by equation (1) of :mod:`novelty.maps.tiles`; -1 when
    ``t`` is (the tile is not held)."""
    if t < 0:
        return -1
    return t * TILE_CELLS + ((i & _MASK) << TILE_SHIFT) + (j & _MASK)


@njit(cache=True, error_model="numpy", inline="always")
def unit(table, bits, tiles, i, j):
    """The unit of cell (i, j) by equation (1) of :mod:`novelty.maps.tiles`; -1 when its tile is not held."""
    return unit_in(find(table, bits, tiles, tile_key(i, j)), i, j)


@njit(cache=True, error_model="numpy", inline="always")
def tiles_crossed(x0, y0, x1, y1, cell_size):
    """At most how many tiles a ray's cells lie in: the walk of its tiles' indices, by equation (2)."""
    i0, j0 = np.int64(np.floor(x0 / cell_size)) >> TILE_SHIFT, np.int64(np.floor(y0 / cell_size)) >> TILE_SHIFT
    i1, j1 = np.int64(np.floor(x1 / cell_size)) >> TILE_SHIFT, np.int64(np.floor(y1 / cell_size)) >> TILE_SHIFT
    return abs(i1 - i0) + abs(j1 - j0) + 1


@njit(cache=True, error_model="numpy")
def scan_sizes(X, n_sectors, c, max_range, arc, margin, most, out):
    """Each row's cells to walk and echoes (at least ``most + 1`` where its rays alone are more than ``most``)
    into ``out``, and the longest walk of a ray, ``(longest, sectors cut)``: what a scan will cost, known
    before any is learned."""
    longest, cut = 0, 0
    for r in range(X.shape[0]):
        x, y = X[r, 0], X[r, 1]
        near, ex, ey = X[r, 3:3 + n_sectors], X[r, 3 + n_sectors:3 + 2 * n_sectors], X[r, 3 + 2 * n_sectors:]
        count = ray_count(x, y, ex, ey, arc, c, max_range)
        if count > most:
            out[r] = count
            continue
        hit = np.empty(count, dtype=np.bool_)
        end_x, end_y, free_x, free_y = np.empty(count), np.empty(count), np.empty(count), np.empty(count)
        m, cut_here = rays(x, y, near, ex, ey, arc, c, max_range, margin, hit, end_x, end_y, free_x, free_y)
        cut += cut_here
        total = 0
        for k in range(m):
            total += hit[k]
            if not np.isnan(free_x[k]):
                n = length(x, y, free_x[k], free_y[k], c)
                total += n
                longest = max(longest, n)
        out[r] = total
    return longest, cut


@njit(cache=True, error_model="numpy")
def scan_bounds(X, n_sectors, c, max_range, arc, margin, most, sizes, widths):
    """Each row's cone width into ``widths`` (``arc``; where it is negative, as wide as a sector stands for) and
    at most how many cells its rays touch into ``sizes``; returns ``(the most rays of a row, at most how many
    cells a ray's walk passes, sectors cut)``: what a scan will cost, known before any is learned.

    A ray of length ``L`` passes at most ``1.5 L / c + 3`` cells by equation (2) (``|di| + |dj| <= sqrt(2) L /
    c + 2``, whatever the rounding of coordinates within :data:`~novelty.io.scans.points.MAX_COORDINATE`), and
    hits one: each sector's ``cone_rays`` rays are as long as it. Where that bound exceeds ``most``, the row's
    cells are counted exactly (:func:`scan_sizes`: at least ``most + 1`` where they are more than ``most``), so
    a row over ``most`` is one whose scan would touch more cells.
    """
    most_rays, longest, cut = 1, 0, 0
    for r in range(X.shape[0]):
        x, y = X[r, 0], X[r, 1]
        ex, ey = X[r, 3 + n_sectors:3 + 2 * n_sectors], X[r, 3 + 2 * n_sectors:]
        widths[r] = sector_width(x, y, ex, ey) if arc < 0.0 else arc
        reach, walks, ray_walk = 0.0, 0.0, 0
        for k in range(n_sectors):
            dx, dy = ex[k] - x, ey[k] - y
            length = np.sqrt(dx * dx + dy * dy)   # as scan_rays measures a sector, cut at max_range
            if length > max_range:
                length = max_range
                cut += 1
            reach = max(reach, length)
            walk = np.floor(1.5 * length / c) + 4.0
            walks += walk + 1.0
            ray_walk = max(ray_walk, np.int64(min(walk, 2.0**62)))
        cones = cone_rays(widths[r], reach, c)
        most_rays = max(most_rays, n_sectors * cones)
        if cones * walks <= most:
            sizes[r] = np.int64(cones * walks)
            longest = max(longest, ray_walk)
        else:
            exact, _ = scan_sizes(X[r:r + 1], n_sectors, c, max_range, arc, margin, most, sizes[r:r + 1])
            longest = max(longest, exact)
    return most_rays, longest, cut


def check_costs(X, grid, arc: float, margin: float, what: str = "rays", widths=None) -> tuple[np.ndarray, int]:
    """Refuse rows with a scan that would touch more than ``grid.max_scan_cells`` cells, before anything is
    learned (a ValueError naming the row), and warn of sectors cut at ``grid.max_range``
    (:class:`~novelty.maps.scan_rays.MapRangeWarning`). ``grid``: the component whose bounds these are (its
    ``cell_size``, ``max_range``, ``max_scan_cells``). Returns at most how many cells each row's scan touches
    and a ray's walk passes (:func:`scan_bounds`: what to make room for); ``widths``, an array of a value a
    row, receives each row's cone width, by which a map reads it."""
    n = (X.shape[1] - 3) // 3
    sizes = np.empty(X.shape[0], dtype=np.int64)
    widths = np.empty(X.shape[0]) if widths is None else widths
    _, longest, cut = scan_bounds(X, n, float(grid.cell_size), float(grid.max_range), arc, margin,
                                  int(grid.max_scan_cells), sizes, widths)
    name = type(grid).__name__
    over = np.flatnonzero(sizes > grid.max_scan_cells)
    if over.size:
        raise ValueError(f"{name}: the scan of row {over[0]} would touch {sizes[over[0]]} cells or more, more than "
                         f"max_scan_cells = {grid.max_scan_cells} (its {what} up to max_range = "
                         f"{grid.max_range:g} m, in cells of {grid.cell_size:g} m); nothing was learned. Lower "
                         "max_range, or raise cell_size or max_scan_cells.")
    if cut:
        warnings.warn(f"{cut} sectors end beyond max_range = {grid.max_range:g} m from the robot: {name} reads each "
                      "as no echo, its free space up to max_range (set max_range to the sensor's range to read "
                      "them whole).", _scan.MapRangeWarning, stacklevel=5)
    return sizes, int(longest)
