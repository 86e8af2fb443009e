"""Habituating synapse models: one module per model, all behind :class:`Synapse`."""

from .base import Synapse
from .staddon_higa import StaddonHigaSynapse
from .stanley import StanleySynapse
from .wang_hsu import WangHsuSynapse

__all__ = ["Synapse", "StanleySynapse", "WangHsuSynapse", "StaddonHigaSynapse"]
