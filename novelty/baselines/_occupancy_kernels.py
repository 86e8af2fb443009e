"""The occupancy grid's scoring and learning, compiled: :class:`~novelty.baselines.occupancy_grid.OccupancyGrid`'s loop.

One call runs the rows of a batch in order: each scan's rays
(:func:`novelty.maps.grid_kernels.rays`, each sector on its axis), its novelty
against the grid as it is, then, learning, its update. It stops before a scan
whose new tiles might not fit in the arrays it was given, and says how many
tiles it needs (``counters[NEED]``): the caller makes room and calls again from
there. Plain numba over arrays, as the project's other kernels; the tests
compare it with a readable grid of dictionaries.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..maps.grid_kernels import add, find, rays, tile_key, tiles_crossed, walk
from ..maps.tiles import TILE_CELLS, TILE_SHIFT

__all__ = ["run", "N_TILES", "STAMP", "NEED", "PASSED", "FREE", "OCCUPIED", "BOTH"]

#: the counters: tiles held, the last stamp given, tiles a scan needs room for, cells passed by (grid full)
N_TILES, STAMP, NEED, PASSED = 0, 1, 2, 3
#: the evidence's codes (the order of OccupancyGrid's rule)
FREE, OCCUPIED, BOTH = 0, 1, 2

_MASK = (1 << TILE_SHIFT) - 1


@njit(cache=True, error_model="numpy", inline="always")
def _unit(table, bits, tiles, counters, i, j, make, max_tiles):
    """Cell (i, j)'s unit; -1 when its tile is not held (and, with ``make``, cannot be made)."""
    key = tile_key(i, j)
    t = find(table, bits, tiles, key)
    if t < 0:
        if not make:
            return -1
        if counters[N_TILES] >= max_tiles:
            counters[PASSED] += 1
            return -1
        t = counters[N_TILES]
        add(table, bits, tiles, t, key)
        counters[N_TILES] = t + 1
    return t * TILE_CELLS + ((i & _MASK) << TILE_SHIFT) + (j & _MASK)


@njit(cache=True, error_model="numpy")
def _score(x, y, hit, end_x, end_y, free_x, free_y, m, c, log_odds, table, bits, tiles, counters, evidence,
           free_below, occupied_above, tolerance, cells):
    """The share of a scan's rays whose evidence contradicts the grid (OccupancyGrid's equation (3))."""
    conflicts, rays_counted = 0, 0
    for k in range(m):
        conflict = False
        ie, je = math.floor(end_x[k] / c), math.floor(end_y[k] / c)
        if evidence != OCCUPIED and hit[k]:   # its echo in cells the grid holds free
            free = True
            for di in range(-tolerance, tolerance + 1):
                for dj in range(-tolerance, tolerance + 1):
                    u = _unit(table, bits, tiles, counters, ie + di, je + dj, False, 0)
                    if u < 0 or not log_odds[u] < free_below:
                        free = False
            conflict = free
        if evidence != FREE and not conflict and not math.isnan(free_x[k]):   # its beam through occupied cells
            n = walk(x, y, free_x[k], free_y[k], c, cells)
            for q in range(n):
                i, j = cells[q, 0], cells[q, 1]
                if hit[k] and abs(i - ie) <= tolerance and abs(j - je) <= tolerance:
                    continue
                u = _unit(table, bits, tiles, counters, i, j, False, 0)
                if u >= 0 and log_odds[u] > occupied_above:
                    conflict = True
                    break
        conflicts += conflict
        rays_counted += 1 if evidence != FREE else hit[k]
    return conflicts / rays_counted if rays_counted else 0.0


@njit(cache=True, error_model="numpy")
def _update(x, y, hit, end_x, end_y, free_x, free_y, m, c, log_odds, stamp, table, bits, tiles, counters,
            max_tiles, hit_step, miss_step, low, high, cells):
    """One scan's inverse sensor model: each cell once, occupied where an echo lies, else free where a beam
    passed (OccupancyGrid's equations (1) and (2))."""
    counters[STAMP] += 1
    s = counters[STAMP]
    for k in range(m):
        if hit[k]:
            u = _unit(table, bits, tiles, counters, math.floor(end_x[k] / c), math.floor(end_y[k] / c), True,
                      max_tiles)
            if u >= 0 and stamp[u] != s:
                stamp[u] = s
                log_odds[u] = min(high, log_odds[u] + hit_step)
    for k in range(m):
        if math.isnan(free_x[k]):
            continue
        n = walk(x, y, free_x[k], free_y[k], c, cells)
        for q in range(n):
            u = _unit(table, bits, tiles, counters, cells[q, 0], cells[q, 1], True, max_tiles)
            if u >= 0 and stamp[u] != s:
                stamp[u] = s
                log_odds[u] = max(low, log_odds[u] + miss_step)


@njit(cache=True, error_model="numpy")
def run(X, start, n_sectors, c, max_range, max_ray_cells, learn, hit_step, miss_step, low, high, evidence,
        free_below, occupied_above, tolerance, tiles, table, bits, log_odds, stamp, counters, max_tiles, novelty):
    """Score (and, with ``learn``, learn) the rows ``X[start:]`` in order, each scan's novelty into
    ``novelty``; returns the first row not done (``X.shape[0]`` when all are). The caller checked that no
    ray passes through more than ``max_ray_cells`` cells."""
    hit = np.empty(n_sectors, dtype=np.bool_)
    end_x, end_y = np.empty(n_sectors), np.empty(n_sectors)
    free_x, free_y = np.empty(n_sectors), np.empty(n_sectors)
    cells = np.empty((max_ray_cells, 2), dtype=np.int64)
    limit = min(max_tiles, tiles.shape[0])
    for r in range(start, X.shape[0]):
        x, y = X[r, 0], X[r, 1]
        near, ex, ey = X[r, 3:3 + n_sectors], X[r, 3 + n_sectors:3 + 2 * n_sectors], X[r, 3 + 2 * n_sectors:]
        m, _ = rays(x, y, near, ex, ey, 0.0, c, max_range, 0.0, hit, end_x, end_y, free_x, free_y)
        if learn:
            need = counters[N_TILES]
            for k in range(m):
                need += tiles_crossed(x, y, end_x[k], end_y[k], c)
            if need > tiles.shape[0] and tiles.shape[0] < max_tiles:
                counters[NEED] = min(need, max_tiles)
                return r
        novelty[r] = _score(x, y, hit, end_x, end_y, free_x, free_y, m, c, log_odds, table, bits, tiles,
                            counters, evidence, free_below, occupied_above, tolerance, cells)
        if learn:
            _update(x, y, hit, end_x, end_y, free_x, free_y, m, c, log_odds, stamp, table, bits, tiles, counters,
                    limit, hit_step, miss_step, low, high, cells)
    return X.shape[0]
