"""Tiles: a cell's unit by equation (1), found by sorted keys (numpy) and by the compiled hash table alike."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.maps import grid_kernels as kernels
from novelty.maps.tiles import TILE_CELLS, TileIndex, cell_of_unit, local_units, tile_keys


def test_a_cell_lies_in_the_tile_of_its_indices_floor_divided_by_16():
    i, j = np.array([0, 15, 16, -1, -16, -17]), np.array([0, 0, 31, -1, 5, -17])
    assert (tile_keys(i, j) >> 32).tolist() == [2**30 + t for t in (0, 0, 1, -1, -1, -2)]
    assert ((tile_keys(i, j) & 0xFFFFFFFF) - 2**31).tolist() == [0, 0, 1, -1, 0, -2]
    assert local_units(i, j).tolist() == [0, 15 * 16, 15, 255, 5, 15 * 16 + 15]


cells = st.lists(st.tuples(st.integers(-10**6, 10**6), st.integers(-10**6, 10**6)), min_size=1, max_size=60)


@settings(max_examples=200, deadline=None)
@given(cells)
def test_units_and_cells_round_trip_and_both_indexes_agree(points):
    i, j = (np.array(v, dtype=np.int64) for v in zip(*points))
    keys = tile_keys(i, j)
    tiles = np.unique(keys)[::-1].copy()                 # any order: the order the tiles were made
    index = TileIndex(tiles[: tiles.size // 2 + 1])      # some tiles held, some not
    units = index.units(i, j)
    held = units >= 0
    assert np.array_equal(held, np.isin(keys, index.tiles))
    np.testing.assert_array_equal(cell_of_unit(units[held], index.tiles), np.c_[i, j][held])
    assert np.all(units[held] // TILE_CELLS == index.find(keys[held]))
    # the compiled table holds the same tiles in the same order
    capacity = index.tiles.size
    bits = kernels.bits_for(capacity)
    table = kernels.table_of(index.tiles, capacity, bits)
    assert [kernels.unit(table, bits, index.tiles, a, b) for a, b in zip(i.tolist(), j.tolist())] == units.tolist()


def test_the_table_is_at_most_half_full_and_adding_keeps_the_order():
    assert kernels.bits_for(1) == 4 and kernels.bits_for(9) == 5 and kernels.bits_for(1000) == 11
    tiles = np.full(40, -1, dtype=np.int64)
    bits = kernels.bits_for(40)
    table = np.full(1 << bits, -1, dtype=np.int64)
    keys = tile_keys(np.arange(40) * 16, np.arange(40) * -16)
    for n, key in enumerate(keys):
        assert kernels.find(table, bits, tiles, key) == -1
        kernels.add(table, bits, tiles, n, key)
    assert [kernels.find(table, bits, tiles, key) for key in keys] == list(range(40))
    assert tiles.tolist() == keys.tolist()
