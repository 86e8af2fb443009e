"""The cells of square side ``c`` a straight ray passes through, in order: a voxel traversal.

Cell ``(i, j)`` holds the points ``i c <= x < (i + 1) c``, ``j c <= y < (j + 1) c``
(``i = floor(x / c)``). A ray from ``p0 = (x0, y0)`` to ``p1 = (x1, y1)``,
``p(t) = p0 + t (p1 - p0)`` for ``t`` in [0, 1], starts in the cell of ``p0``
and ends in the cell of ``p1``; between them it crosses ``|i1 - i0|`` vertical
and ``|j1 - j0|`` horizontal cell boundaries, each at the ``t`` where it meets
the boundary's line::

    t_x = (b c - x0) / (x1 - x0)      b = i + 1 stepping right, b = i stepping left     (1)

(``i`` the current cell's column) and likewise ``t_y``. The traversal of
Amanatides & Woo (1987) steps, at every crossing, to the neighbour across the
boundary met first, the one of least ``t``: so a ray visits::

    n = |i1 - i0| + |j1 - j0| + 1                                                (2)

cells, each sharing a side with the one before, at a cost linear in its
length. Two choices of ours, stated:

- each ``t`` is computed from its boundary by (1), not accumulated by adding
  ``c / |x1 - x0|`` at every step as Amanatides & Woo do, so a long ray does
  not drift by the rounding of its additions;
- a crossing of both boundaries at one ``t`` (the ray through a cell's
  corner) steps first across the one it crosses upwards or rightwards (the
  vertical one when it crosses both the same way): a point on a boundary
  belongs to the cell above or right of it, so the walk then visits the cell
  that holds the corner, and one of the two cells beside it, which the ray
  only touches. A ray along a boundary line lies in the cells on the line's
  upper (right) side, as its points do. So every point of the ray lies in a
  cell of the walk, and every cell of the walk touches the ray.

The steps never cross more boundaries of an axis than (2) allows, so a ray
ends in the cell of its end point whatever the rounding of (1) near a
corner. :func:`walk_into` is the traversal, one ray, in plain Python (the
specification; :mod:`novelty.maps.grid_kernels` compiles this function as
it is); :func:`walk_rays` gives the cells of many rays at once with numpy,
the crossings of each ray sorted by their ``t`` (the same cells, in the same
order: the tests check the three against each other and against exact
rational arithmetic). Coordinates must satisfy ``|x / c| < 2**52``, so that
the cells' indices are exact integers.

References
----------
Amanatides, J. & Woo, A. (1987). A fast voxel traversal algorithm for ray
tracing. Proc. Eurographics '87, 3-10.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["walk_into", "walk_length", "walk_cells", "walk_rays", "walk_lengths"]


def walk_length(x0, y0, x1, y1, cell_size):
    """The number of cells the ray from (x0, y0) to (x1, y1) passes through: equation (2).

    >>> walk_length(0.02, 0.05, 0.28, 0.19, 0.1)
    4
    """
    c = cell_size
    return (abs(math.floor(x1 / c) - math.floor(x0 / c)) + abs(math.floor(y1 / c) - math.floor(y0 / c)) + 1)


def walk_into(x0, y0, x1, y1, cell_size, out):
    """Write the cells (i, j) the ray from (x0, y0) to (x1, y1) passes through into ``out[:n]``, in order; return n.

    ``out`` is an int64 array of shape (at least :func:`walk_length`, 2). The
    traversal of the module docstring: the next boundary crossed is the one of
    least ``t`` (1); on a tie, the one crossed upwards or rightwards (the
    vertical one when both are crossed the same way).
    """
    c = cell_size
    i, j = math.floor(x0 / c), math.floor(y0 / c)
    left_i, left_j = abs(math.floor(x1 / c) - i), abs(math.floor(y1 / c) - j)
    dx, dy = x1 - x0, y1 - y0
    step_i, step_j = (1 if dx > 0 else -1), (1 if dy > 0 else -1)
    vertical_first = step_i > 0 or step_j < 0   # on a tie: the boundary crossed upwards or rightwards
    # t of the next crossing of each axis, by (1) (the sides of the current cell)
    t_x = ((i + (step_i > 0)) * c - x0) / dx if left_i else 0.0
    t_y = ((j + (step_j > 0)) * c - y0) / dy if left_j else 0.0
    out[0, 0], out[0, 1] = i, j
    n = 1
    while left_i or left_j:
        if left_i and (not left_j or t_x < t_y or (t_x == t_y and vertical_first)):
            i += step_i
            left_i -= 1
            t_x = ((i + (step_i > 0)) * c - x0) / dx
        else:
            j += step_j
            left_j -= 1
            t_y = ((j + (step_j > 0)) * c - y0) / dy
        out[n, 0], out[n, 1] = i, j
        n += 1
    return n


def walk_cells(start, end, cell_size) -> np.ndarray:
    """The cells (i, j) a ray passes through from ``start`` to ``end`` (points in m), in order: shape (n, 2).

    >>> walk_cells((0.02, 0.05), (0.28, 0.19), 0.1).tolist()
    [[0, 0], [1, 0], [1, 1], [2, 1]]
    >>> walk_cells((0.25, 0.25), (0.75, 0.75), 0.5).tolist()    # through a corner: the vertical side first
    [[0, 0], [1, 0], [1, 1]]
    >>> walk_cells((0.25, 0.25), (-0.25, 0.75), 0.5).tolist()   # left and up: the horizontal first
    [[0, 0], [0, 1], [-1, 1]]
    >>> walk_cells((0.25, 0.3), (0.25, 0.3), 0.1).tolist()   # a ray of length 0: its cell
    [[2, 2]]
    """
    (x0, y0), (x1, y1) = (float(v) for v in start), (float(v) for v in end)
    out = np.empty((walk_length(x0, y0, x1, y1, cell_size), 2), dtype=np.int64)
    walk_into(x0, y0, x1, y1, float(cell_size), out)
    return out


def walk_lengths(starts, ends, cell_size) -> np.ndarray:
    """Equation (2) for rays from ``starts`` (m, 2) to ``ends`` (m, 2): the cells each passes through (int64)."""
    start_cells = np.floor(np.asarray(starts, dtype=np.float64) / cell_size)
    end_cells = np.floor(np.asarray(ends, dtype=np.float64) / cell_size)
    return (np.abs(end_cells - start_cells).sum(axis=1) + 1).astype(np.int64)


def walk_rays(starts, ends, cell_size) -> tuple[np.ndarray, np.ndarray]:
    """The cells of many rays at once: ``(cells (N, 2) int64, offsets (m + 1,))``, ray ``r``'s cells
    in order at ``cells[offsets[r]:offsets[r + 1]]``.

    The same cells as :func:`walk_into` ray by ray: each ray's crossings, with
    ``t`` by (1) exactly as it computes them, sorted by ``t``, then (a tie) by
    which it crosses first (a stable sort: the crossings of one axis in turn).

    >>> cells, offsets = walk_rays([[0.02, 0.05], [0.0, 0.0]], [[0.28, 0.19], [-0.15, 0.0]], 0.1)
    >>> cells.tolist(), offsets.tolist()
    ([[0, 0], [1, 0], [1, 1], [2, 1], [0, 0], [-1, 0], [-2, 0]], [0, 4, 7])
    """
    p0 = np.asarray(starts, dtype=np.float64).reshape(-1, 2)
    p1 = np.asarray(ends, dtype=np.float64).reshape(-1, 2)
    c = float(cell_size)
    first = np.floor(p0 / c).astype(np.int64)
    steps = np.abs(np.floor(p1 / c).astype(np.int64) - first)
    delta = p1 - p0
    sign = np.where(delta > 0, 1, -1)
    counts = steps.sum(axis=1) + 1
    offsets = np.zeros(p0.shape[0] + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    # every crossing: its ray, its axis (0 vertical, 1 horizontal), its t by (1)
    rays, axes, ts = [], [], []
    for axis in (0, 1):
        n = steps[:, axis]
        ray = np.repeat(np.arange(p0.shape[0]), n)
        k = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)   # the k-th crossing of this axis
        s = sign[ray, axis]
        boundary = first[ray, axis] + s * k + (s > 0)          # the current cell's side, as walk_into has it
        ts.append((boundary * c - p0[ray, axis]) / delta[ray, axis])
        rays.append(ray)
        axes.append(np.full(ray.size, axis))
    ray, axis, t = np.concatenate(rays), np.concatenate(axes), np.concatenate(ts)
    # on a tie the boundary crossed upwards or rightwards first: the vertical unless the ray goes left and up
    later = axis ^ ((sign[ray, 0] < 0) & (sign[ray, 1] > 0))
    order = np.lexsort((later, t, ray))
    ray, axis = ray[order], axis[order]
    # each crossing moves its ray one cell along its axis, into every row of the ray but its first
    first_rows = np.zeros(offsets[-1], dtype=bool)
    first_rows[offsets[:-1]] = True
    moves = np.zeros((offsets[-1], 2), dtype=np.int64)
    moves[np.flatnonzero(~first_rows), axis] = sign[ray, axis]
    # a ray's cells: its first cell plus its moves so far
    total = np.cumsum(moves, axis=0)
    return total - np.repeat(total[offsets[:-1]] - first, counts, axis=0), offsets

