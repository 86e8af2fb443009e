"""The cells of a world grid held in tiles: memory for the area seen, with a stated bound.

A grid of the world (a map's cells, an occupancy grid's) meets cells only where
a robot's rays go, anywhere in a plane. It holds them in square tiles of
``TILE x TILE`` cells (16 x 16: 1.6 m at cells of 0.1 m), made when a ray first
meets one of their cells: a tile is a block of ``TILE_CELLS`` consecutive
units in every per-cell array, in the order the tiles were made, so the memory
grows with the area seen (a whole tile at a time), never with the scans. Cell
``(i, j)`` lies in tile ``(i >> 4, j >> 4)`` (floor division by 16, negative
indices included), at the unit

    tile's order * TILE_CELLS + (i mod 16) * 16 + (j mod 16)                    (1)

A grid holds at most ``max_cells`` cells (whole tiles); a cell of a tile it
has no room for is read as never met, and learning passes it by (a
:class:`GridFullWarning` says how many such cells a call met).

The tiles are found by their keys (:func:`tile_keys`): in the compiled
kernels through an open-addressing hash table of the keys
(:mod:`novelty.maps.grid_kernels`, Knuth's multiplicative hashing with
linear probing), in the numpy references through the keys sorted
(:class:`TileIndex`). Neither is part of the state: both are rebuilt from the
tiles' keys, in the order they were made.

References
----------
Knuth, D. E. (1998). The Art of Computer Programming, vol. 3, 2nd ed.,
section 6.4 (multiplicative hashing, linear probing).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TILE", "TILE_SHIFT", "TILE_CELLS", "GridFullWarning", "tile_keys", "local_units", "cell_of_unit",
           "TileIndex"]

#: cells along a tile's side, as a shift: 16
TILE_SHIFT = 4
TILE = 1 << TILE_SHIFT
#: cells in a tile: the units a tile adds to every per-cell array
TILE_CELLS = TILE * TILE
_MASK = TILE - 1
_SHIFT_I, _SHIFT_J = np.int64(1 << 30), np.int64(1 << 31)


class GridFullWarning(UserWarning):
    """A grid of the world met cells beyond its ``max_cells``: it read them as never met and did not learn them."""


def tile_keys(i, j) -> np.ndarray:
    """The key of the tile of each cell (i, j): its indices packed into one int64, ``(ti + 2^30) 2^32 + tj + 2^31``.

    >>> tile_keys(np.array([0, 15, 16, -1]), np.array([0, 0, 0, -17])).tolist() == [
    ...     2**62 + 2**31, 2**62 + 2**31, (2**30 + 1) * 2**32 + 2**31, (2**30 - 1) * 2**32 + 2**31 - 2]
    True
    """
    ti, tj = np.asarray(i, dtype=np.int64) >> TILE_SHIFT, np.asarray(j, dtype=np.int64) >> TILE_SHIFT
    return ((ti + _SHIFT_I) << np.int64(32)) + (tj + _SHIFT_J)


def local_units(i, j) -> np.ndarray:
    """Each cell's place within its tile: ``(i mod 16) 16 + (j mod 16)``."""
    return ((np.asarray(i, dtype=np.int64) & _MASK) << TILE_SHIFT) + (np.asarray(j, dtype=np.int64) & _MASK)


def cell_of_unit(units, tiles) -> np.ndarray:
    """The cell (i, j) of each unit, given the tiles' keys in the order they were made: shape (n, 2).

    >>> tiles = tile_keys(np.array([-17]), np.array([40]))
    >>> cell_of_unit(np.array([0, 255]), tiles).tolist()
    [[-32, 32], [-17, 47]]
    """
    units = np.asarray(units, dtype=np.int64)
    key = np.asarray(tiles, dtype=np.int64)[units >> (2 * TILE_SHIFT)]
    ti, tj = (key >> np.int64(32)) - _SHIFT_I, (key & np.int64(0xFFFFFFFF)) - _SHIFT_J
    local = units & (TILE_CELLS - 1)
    return np.c_[(ti << TILE_SHIFT) + (local >> TILE_SHIFT), (tj << TILE_SHIFT) + (local & _MASK)]


class TileIndex:
    """The tiles of a grid found by key with numpy: their keys sorted, for the references.

    >>> index = TileIndex(tile_keys(np.array([0, 16]), np.array([0, 0])))
    >>> index.units(np.array([1, 17, 40]), np.array([2, 3, 0])).tolist()   # tiles 0, 1, and none
    [18, 275, -1]
    """

    def __init__(self, tiles: np.ndarray):
        self.tiles = np.asarray(tiles, dtype=np.int64)
        self._order = np.argsort(self.tiles, kind="stable")
        self._sorted = self.tiles[self._order]

    def find(self, keys: np.ndarray) -> np.ndarray:
        """The order of each key's tile, -1 where there is none."""
        keys = np.asarray(keys, dtype=np.int64)
        if self._sorted.size == 0:
            return np.full(keys.shape, -1, dtype=np.int64)
        at = np.searchsorted(self._sorted, keys)
        known = at < self._sorted.size
        known[known] = self._sorted[at[known]] == keys[known]
        return np.where(known, self._order[np.minimum(at, self._sorted.size - 1)], -1)

    def units(self, i, j) -> np.ndarray:
        """Each cell's unit by (1), -1 for a cell of a tile not held."""
        tile = self.find(tile_keys(i, j))
        return np.where(tile >= 0, tile * TILE_CELLS + local_units(i, j), -1)

    def add(self, keys: np.ndarray) -> None:
        """Hold the tiles of ``keys`` too (unique, none held yet), after those held, in their order."""
        self.__init__(np.concatenate([self.tiles, np.asarray(keys, dtype=np.int64)]))
