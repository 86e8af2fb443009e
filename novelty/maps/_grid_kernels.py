"""The grid walk of :mod:`novelty.maps.grid_walk`, compiled: :func:`walk` is :func:`~novelty.maps.grid_walk.walk_into` as it is.

Plain numba over arrays, as the project's other kernels; imported only where
a compiled map or grid needs it (numba's import and the first compilation,
cached on disk after, cost about a second).
"""

from __future__ import annotations

from .._jit import compiled
from .grid_walk import walk_into, walk_length

__all__ = ["walk", "length"]

#: the cells of one ray into ``out[:n]``, in order; returns n (``walk_into`` compiled)
walk = compiled(walk_into)
#: equation (2) of :mod:`novelty.maps.grid_walk`: the cells a ray passes through
length = compiled(walk_length)
