"""The compiled counterparts of :mod:`._graph` and of the winner search, for the step modules.

The same operations as the numpy versions, on arrays with room for more units
(the first ``n`` rows in use): ``A`` is the age matrix (``NO_EDGE`` = no
edge), ``WT`` the weights transposed, (features, capacity), as the driver
holds them. Deleting units shifts the later rows down, as ``np.delete`` does.
"""

from __future__ import annotations

from .._jit import step
from .._kernels._distances import first_least
from ._graph import NO_EDGE


@step
def nearest(d, n):
    """The first unit of least distance (``np.argmin``; ``d`` the squared distances)."""
    return first_least(d, n)


@step
def runner_up(d, n, s):
    """``np.argmin`` with unit ``s`` at infinity (0 when ``s`` is the only unit)."""
    t = -1
    for j in range(n):
        if j != s and (t < 0 or d[j] < d[t]):
            t = j
    return 0 if t < 0 else t


@step
def neighbours(A, n, row, nb):
    """_graph.neighbours into ``nb``; returns how many."""
    k = 0
    for j in range(n):
        if A[row, j] >= 0:
            nb[k] = j
            k += 1
    return k


@step
def age_edges(A, n, row):
    for j in range(n):
        if A[row, j] >= 0:
            A[row, j] += 1
            A[j, row] += 1


@step
def connect(A, i, j, age):
    """An edge of ``age`` (``NO_EDGE``: disconnect)."""
    A[i, j] = age
    A[j, i] = age


@step
def prune(A, n, row, max_age, isolated):
    """_graph.prune: drop the edges of ``row`` older than ``max_age``; mark the units left
    alone in ``isolated`` (which it clears first) and return how many."""
    any_old = False
    for j in range(n):
        isolated[j] = False
        if A[row, j] > max_age:
            connect(A, row, j, NO_EDGE)
            isolated[j] = True  # a candidate for now
            any_old = True
    if not any_old:
        return 0
    isolated[row] = True
    count = 0
    for c in range(n):
        if isolated[c]:
            for j in range(n):
                if A[c, j] >= 0:
                    isolated[c] = False
                    break
            if isolated[c]:
                count += 1
    return count


@step
def delete_units(n, gone, WT, A, ids, u):
    """np.delete of the units marked in ``gone`` from WT (columns), A (rows and columns),
    ``ids`` and ``u``; returns the units left. ``gone`` is left as it is (the driver
    deletes the synapses' rows by it)."""
    keep = 0
    for j in range(n):
        if gone[j]:
            continue
        if keep != j:
            for k in range(WT.shape[0]):  # element loops: slice assignment compiles slowly
                WT[k, keep] = WT[k, j]
            ids[keep] = ids[j]
            u[keep] = u[j]
            for i in range(n):
                A[keep, i] = A[j, i]
        keep += 1
    for i in range(keep):
        col = 0
        for j in range(n):
            if not gone[j]:
                A[i, col] = A[i, j]
                col += 1
    for i in range(keep):
        for j in range(keep, n):
            A[i, j] = NO_EDGE
            A[j, i] = NO_EDGE
    return keep


@step
def new_unit(A, n):
    """Row ``n`` of ``A`` without edges (a unit about to be added)."""
    for j in range(n + 1):
        A[n, j] = NO_EDGE
        A[j, n] = NO_EDGE
