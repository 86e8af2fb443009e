"""Clustering networks: one module per network, all behind :class:`Clusterer`."""

from .base import Clusterer, Growth, Match
from .som import SOM

__all__ = ["Clusterer", "Growth", "Match", "SOM"]
