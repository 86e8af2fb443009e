"""Clustering networks: one module per network, all behind :class:`Clusterer`."""

from .base import Clusterer, Growth, Match
from .gng import GrowingNeuralGas
from .gwr import GrowWhenRequired
from .kmeans import OnlineKMeans
from .som import SOM

__all__ = ["Clusterer", "Growth", "Match", "SOM", "GrowingNeuralGas", "GrowWhenRequired", "OnlineKMeans"]
