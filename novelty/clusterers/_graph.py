"""The undirected graph of edges with ages shared by the growing networks (GNG, GWR).

The graph is one square matrix ``ages`` of shape (n_units, n_units) and
integer type: ``ages[i, j]`` is the age of the edge between rows ``i`` and
``j``, or ``NO_EDGE`` (-1) when there is none. It is symmetric with ``NO_EDGE``
on the diagonal. A flat matrix keeps every operation a row or column slice,
which a compiled kernel can take over unchanged, and it is a plain array a
model file holds as it is.

Also here: the initialisation the networks (and online k-means) start from.
"""

from __future__ import annotations


import numpy as np

from .._component import StateError, check_array_state

__all__ = [
    "NO_EDGE",
    "AGE_DTYPE",
    "empty_graph",
    "neighbours",
    "connect",
    "disconnect",
    "age_edges",
    "prune",
    "add_units",
    "delete_units",
    "edge_list",
    "check_graph",
    "initial_weights",
]

NO_EDGE = -1
AGE_DTYPE = np.int32


def empty_graph(n_units: int) -> np.ndarray:
    """An ``(n_units, n_units)`` age matrix without edges."""
    return np.full((n_units, n_units), NO_EDGE, dtype=AGE_DTYPE)


def neighbours(ages: np.ndarray, row: int) -> np.ndarray:
    """Rows connected to ``row`` (its topological neighbours), ascending."""
    return np.flatnonzero(ages[row] >= 0)


def connect(ages: np.ndarray, i: int, j: int) -> None:
    """Create the edge i-j with age 0, or reset its age to 0 if it exists."""
    ages[i, j] = ages[j, i] = 0


def disconnect(ages: np.ndarray, i: int, j: int) -> None:
    """Remove the edge i-j (if any)."""
    ages[i, j] = ages[j, i] = NO_EDGE


def age_edges(ages: np.ndarray, row: int) -> None:
    """Increase by one the age of every edge with an end at ``row``."""
    nb = neighbours(ages, row)
    ages[row, nb] += 1
    ages[nb, row] += 1


def prune(ages: np.ndarray, row: int, max_age: int) -> np.ndarray:
    """Remove the edges of ``row`` older than ``max_age``; return the units left without edges.

    Only the edges of ``row`` are examined: in both networks they are the
    only edges that age in a step, so no other edge can have passed
    ``max_age``, and only their other ends (or ``row`` itself) can have lost
    their last edge. The returned rows are sorted; the units are not deleted.
    """
    old = np.flatnonzero(ages[row] > max_age)
    if old.size == 0:
        return np.empty(0, dtype=np.intp)
    ages[row, old] = NO_EDGE
    ages[old, row] = NO_EDGE
    candidates = np.append(old, row)
    isolated = candidates[~(ages[candidates] >= 0).any(axis=1)]
    return np.sort(isolated).astype(np.intp)


def add_units(ages: np.ndarray, n: int) -> np.ndarray:
    """The age matrix with ``n`` unconnected units appended."""
    m = ages.shape[0]
    out = empty_graph(m + n)
    out[:m, :m] = ages
    return out


def delete_units(ages: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """The age matrix without the units at ``rows`` (and their edges)."""
    keep = np.ones(ages.shape[0], dtype=bool)
    keep[rows] = False
    return ages[np.ix_(keep, keep)]


def edge_list(ages: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every edge once, as ``(pairs, ages)``: pairs of rows ``i < j``, shape (n_edges, 2)."""
    i, j = np.nonzero(np.triu(ages >= 0, k=1))
    return np.stack([i, j], axis=1), ages[i, j].astype(np.int64)


def check_graph(owner, name: str, n_units: int) -> np.ndarray:
    """Check an age matrix read from a file: square over the units, symmetric, no loops."""
    ages = check_array_state(owner, name, 2, "iu", shape=(n_units, n_units))
    cls = type(owner).__name__
    if not np.array_equal(ages, ages.T):
        raise StateError(f"{cls}.{name} must be symmetric (edges are undirected).")
    if np.any(np.diagonal(ages) != NO_EDGE):
        raise StateError(f"{cls}.{name} must have {NO_EDGE} on its diagonal (no unit is its own neighbour).")
    if ages.size and ages.min() < NO_EDGE:
        raise StateError(f"{cls}.{name} holds negative ages other than {NO_EDGE} (no edge).")
    return ages


def initial_weights(X: np.ndarray, rng: np.random.Generator, n_units: int, init: str,
                    init_range) -> np.ndarray:
    """``n_units`` prototypes: distinct random rows of ``X`` ("sample"), or uniform in ``init_range``.

    With fewer rows than units, "sample" repeats rows (a network started on a
    single scan starts with all its units on that scan).
    """
    if init == "uniform":
        low, high = init_range
        return rng.uniform(low, high, size=(n_units, X.shape[1]))
    rows = rng.choice(X.shape[0], size=n_units, replace=X.shape[0] < n_units)
    return X[rows].copy()
