"""The world cells' part of a habituating map's compiled loop (:mod:`novelty.maps.map_engine`).

What :class:`~novelty.maps.cells.WorldCells` does for one scan, compiled, the
same operations in the same order as its reference (:mod:`novelty.maps.map_engine`):
its cells (:func:`scan_cells`: the rays, the hit cells sorted, the cells passed
ray after ray, the neighbours sorted), its tiles made in the order the cells
meet them (:func:`meet`), its novelty (:func:`readout`, equations (1) and (2)
of :mod:`novelty.maps.cells`), and what it learns besides the synapses'
step (:func:`learn_cells`: the visit rule that picks the winners, the
neighbours, the passes). The synapses' step is the synapse's own, composed by
the driver generated for each synapse (:mod:`novelty.maps._map_driver`).
``p`` is the record of the cells' parameters (:func:`novelty._kernels.params.pack`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._kernels.params import option_code
from .grid_kernels import add, find, ray_count, rays, sector_width, tile_key, unit, unit_in, walk
from .tiles import TILE_CELLS
from .cells import WorldCells

__all__ = ["scan_cells", "meet", "readout", "learn_cells", "pass_scan", "N_TILES", "SCANS", "STAMP", "NEED",
           "PASSED", "HITS"]

HITS = option_code(WorldCells, "evidence", "hits")
#: the counters: tiles held, scans learned, the last stamp given, tiles a scan needs room for, cells passed by
N_TILES, SCANS, STAMP, NEED, PASSED = 0, 1, 2, 3, 4

_SHIFT_I, _SHIFT_J = 1 << 30, 1 << 31


@njit(cache=True, error_model="numpy", inline="always")
def _pack(i, j):
    return ((i + _SHIFT_I) << 32) + (j + _SHIFT_J)


@njit(cache=True, error_model="numpy")
def _unique_sorted(keys, n):
    """Sort ``keys[:n]`` in place and keep each once; returns how many."""
    keys[:n] = np.sort(keys[:n])
    m = 0
    for q in range(n):
        if m == 0 or keys[q] != keys[m - 1]:
            keys[m] = keys[q]
            m += 1
    return m


@njit(cache=True, error_model="numpy")
def scan_cells(x, n, p, arc, hit, end_x, end_y, free_x, free_y, keys, seq, walk_too):
    """One scan's cells into ``seq`` (cells, 2): the hit cells (sorted, each once), then, learning (``walk_too``),
    the cells its rays pass, ray after ray, and (``p.neighbours``) the cells around the hits, none hit, sorted.
    Returns their counts ``(hits, passed, neighbours)``. ``arc``: its cones' width (:func:`cone_width`)."""
    c = p.cell_size
    seq_i, seq_j = seq[:, 0], seq[:, 1]
    near, ex, ey = x[3:3 + n], x[3 + n:3 + 2 * n], x[3 + 2 * n:]
    m, _ = rays(x[0], x[1], near, ex, ey, arc, c, p.max_range, c, hit, end_x, end_y, free_x, free_y)
    h = 0
    for k in range(m):
        if hit[k]:
            keys[h] = _pack(np.int64(math.floor(end_x[k] / c)), np.int64(math.floor(end_y[k] / c)))
            h += 1
    h = _unique_sorted(keys, h)
    for q in range(h):
        seq_i[q], seq_j[q] = (keys[q] >> 32) - _SHIFT_I, (keys[q] & 0xFFFFFFFF) - _SHIFT_J
    at = h
    if walk_too:   # seq has room for them all (the scan's bound, novelty.maps.grid_kernels.scan_bounds)
        for k in range(m):
            if not math.isnan(free_x[k]):
                at += walk(x[0], x[1], free_x[k], free_y[k], c, seq[at:])
    passed = at - h
    q_around = 0
    if walk_too and p.neighbours and h:
        around = np.empty(8 * h, dtype=np.int64)
        for q in range(h):
            for di in range(-1, 2):
                for dj in range(-1, 2):
                    if di or dj:
                        around[q_around] = _pack(seq_i[q] + di, seq_j[q] + dj)
                        q_around += 1
        q_around = _unique_sorted(around, q_around)
        kept, hq = 0, 0
        for q in range(q_around):   # leave out the hit cells: both sorted
            while hq < h and keys[hq] < around[q]:
                hq += 1
            if hq < h and keys[hq] == around[q]:
                continue
            seq_i[at + kept], seq_j[at + kept] = (around[q] >> 32) - _SHIFT_I, (around[q] & 0xFFFFFFFF) - _SHIFT_J
            kept += 1
        q_around = kept
    return h, passed, q_around


@njit(cache=True, error_model="numpy")
def meet(seq_i, seq_j, count, table, bits, tiles, counters, max_tiles, units, new_keys, new_set, set_bits):
    """Make the tiles of ``seq[:count]`` not held yet, in the order the cells meet them, as many as there is
    room for, and each cell's unit into ``units`` (-1: its tile beyond ``max_tiles``). Returns 0, or (nothing
    made) the tiles the arrays need room for."""
    new = 0
    last, t = -1, -1
    set_mask = new_set.shape[0] - 1
    for q in range(count):
        key = tile_key(seq_i[q], seq_j[q])
        if key != last:   # the cells of a ray mostly share a tile: looked up once
            last, t = key, find(table, bits, tiles, key)
            if t < 0:   # a tile to make, once
                slot = np.int64((np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(64 - set_bits))
                while new_set[slot] >= 0 and new_keys[new_set[slot]] != key:
                    slot = (slot + 1) & set_mask
                if new_set[slot] < 0:
                    new_set[slot] = new
                    new_keys[new] = key
                    new += 1
        units[q] = unit_in(t, seq_i[q], seq_j[q])
    for q in range(new):   # the set emptied again
        key = new_keys[q]
        slot = np.int64((np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(64 - set_bits))
        while new_set[slot] >= 0:
            new_set[slot] = -1
            slot = (slot + 1) & set_mask
    if new == 0:
        return 0
    held = counters[N_TILES]
    made = min(new, max(max_tiles - held, 0))
    if held + made > tiles.shape[0]:
        return held + made
    for q in range(made):
        add(table, bits, tiles, held + q, new_keys[q])
    counters[N_TILES] = held + made
    last, t = -1, -1
    for q in range(count):   # the cells of the tiles made now, and those beyond max_tiles
        if units[q] >= 0:
            continue
        key = tile_key(seq_i[q], seq_j[q])
        if key != last:
            last, t = key, find(table, bits, tiles, key)
        units[q] = unit_in(t, seq_i[q], seq_j[q])
        if units[q] < 0:
            counters[PASSED] += 1
    return 0


@njit(cache=True, error_model="numpy")
def readout(seq_i, seq_j, units, h, p, table, bits, tiles, passes, efficacy, fresh, v):
    """The scan's novelty by (2) from its ``h`` hit cells (``seq[:h]``, their ``units``): each one's ``v``
    by (1) into ``v``."""
    if h == 0:
        return 0.0
    t = p.tolerance
    for q in range(h):
        y = math.inf
        own = tile_key(seq_i[q], seq_j[q])   # the cells around a hit cell mostly lie in its tile
        held = units[q] // TILE_CELLS if units[q] >= 0 else -1
        for di in range(-t, t + 1):
            for dj in range(-t, t + 1):
                i, j = seq_i[q] + di, seq_j[q] + dj
                key = tile_key(i, j)
                u = units[q] if di == 0 and dj == 0 else unit_in(held if key == own else find(table, bits, tiles, key),
                                                                 i, j)
                y = min(y, efficacy[u] if u >= 0 else fresh)
        f = passes[units[q]] if units[q] >= 0 else 0.0
        value = y
        if p.evidence != HITS:
            value = y * (p.unseen + (1.0 - p.unseen) * -math.expm1(-f / p.free_scale))
        if p.min_passes > 0 and not (units[q] >= 0 and f >= p.min_passes):
            value = 0.0
        v[q] = value
    ranked = np.sort(v[:h])
    k = p.top if p.has_top else h
    total = 0.0
    for q in range(max(h - k, 0), h):
        total += ranked[q]
    return total / k


@njit(cache=True, error_model="numpy")
def learn_cells(units, h, passed, around, p, passes, last_hit, stamp, counters, winners, nb, now_passes):
    """What a scan learns besides the synapses' step: ``scans_`` counted, the winners (its hit cells at the first
    hit of a visit) into ``winners``, the neighbours into ``nb``, and, with ``now_passes``, the passes of the
    cells its rays passed. Returns ``(winners, neighbours)``."""
    counters[SCANS] += 1
    scans = counters[SCANS]
    w = 0
    for q in range(h):
        u = units[q]
        if u < 0:
            continue
        last = last_hit[u]
        last_hit[u] = scans
        if p.visit_gap == 0 or last == 0 or last < scans - p.visit_gap:
            winners[w] = u
            w += 1
    k = 0
    for q in range(h + passed, h + passed + around):
        if units[q] >= 0:
            nb[k] = units[q]
            k += 1
    if now_passes:
        add_passes(units, h, passed, passes, stamp, counters)
    return w, k


@njit(cache=True, error_model="numpy")
def add_passes(units, h, passed, passes, stamp, counters):
    """One pass to each cell of ``units[h:h + passed]`` once, but to the scan's hit cells ``units[:h]``."""
    counters[STAMP] += 1
    s = counters[STAMP]
    for q in range(h):
        if units[q] >= 0:
            stamp[units[q]] = s
    for q in range(h, h + passed):
        u = units[q]
        if u >= 0 and stamp[u] != s:
            stamp[u] = s
            passes[u] += 1.0


@njit(cache=True, error_model="numpy")
def pass_scan(x, n, p, table, bits, tiles, passes, stamp, counters, hit, end_x, end_y, free_x, free_y, keys,
              seq, units):
    """The passes of a scan learned ``evidence_lag`` scans ago (its tiles made then)."""
    h, passed, _ = scan_cells(x, n, p, cone_width(x, n, p), hit, end_x, end_y, free_x, free_y, keys, seq, True)
    for q in range(h + passed):
        units[q] = unit(table, bits, tiles, seq[q, 0], seq[q, 1])
    add_passes(units, h, passed, passes, stamp, counters)


@njit(cache=True, error_model="numpy")
def score(X, n, p, widths, table, bits, tiles, passes, efficacy, fresh, most_rays, out):
    """The novelty of each row of ``X`` against the map as it is (nothing learned)."""
    hit = np.empty(most_rays, dtype=np.bool_)
    end_x, end_y, free_x, free_y = (np.empty(most_rays), np.empty(most_rays), np.empty(most_rays),
                                    np.empty(most_rays))
    keys = np.empty(most_rays, dtype=np.int64)
    seq = np.empty((most_rays, 2), dtype=np.int64)
    seq_i, seq_j = seq[:, 0], seq[:, 1]
    units = np.empty(most_rays, dtype=np.int64)
    v = np.empty(most_rays)
    for r in range(X.shape[0]):
        h, _, _ = scan_cells(X[r], n, p, widths[r], hit, end_x, end_y, free_x, free_y, keys, seq, False)
        for q in range(h):
            units[q] = unit(table, bits, tiles, seq_i[q], seq_j[q])
        out[r] = readout(seq_i, seq_j, units, h, p, table, bits, tiles, passes, efficacy, fresh, v)


@njit(cache=True, error_model="numpy")
def cone_width(x, n, p):
    """The width of a scan's cones: ``p.arc``, or (``"sector"``) as wide as one of its sectors stands for."""
    return sector_width(x[0], x[1], x[3 + n:3 + 2 * n], x[3 + 2 * n:]) if p.arc_is_sector else p.arc


@njit(cache=True, error_model="numpy")
def most_rays(X, n, p, widths):
    """The most rays a row of ``X`` is read as, its cones ``widths[r]`` wide."""
    most = 1
    for r in range(X.shape[0]):
        x = X[r]
        most = max(most, ray_count(x[0], x[1], x[3 + n:3 + 2 * n], x[3 + 2 * n:], widths[r], p.cell_size,
                                   p.max_range))
    return most
