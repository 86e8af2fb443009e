"""novelty: habituation-based novelty detection.

The reference implementation of the habituating novelty filter of Marsland,
Nehmzow & Shapiro (2000), with interchangeable clusterers and synapse models.

>>> import novelty
>>> det = novelty.make("hsom")            # the paper's detector, every value of the paper
>>> det.clusterer.n_rows, det.synapse.tau_winner
(10, 3.33)

Everything heavy (scikit-learn, the components) is imported on first use, so
``import novelty`` stays cheap; so are the subpackages (``novelty.datasets``,
``novelty.sonar``, ...), each reachable after ``import novelty`` alone. The
registries themselves are ``novelty.registry.detectors``, ``.clusterers`` and
``.synapses``.
"""

from __future__ import annotations

import importlib
from typing import Any

from . import _moved
from . import registry as _registries
from ._markup import plain_descriptions
from ._version import __version__
from .registry import InvalidParameterError, Registry, RegistryError, UnknownNameError

__all__ = [
    "__version__",
    "make",
    "available",
    "load",
    "register_clusterer",
    "register_synapse",
    "register_detector",
    "Registry",
    "RegistryError",
    "UnknownNameError",
    "InvalidParameterError",
    "HabituatingFilter",
    "NoveltyDetector",
    "Clusterer",
    "Synapse",
    "KernelSpec",
    "squared_distances",
    "SOM",
    "StanleySynapse",
    "ModelFileError",
    "FittedPartError",
    "ScanRangeWarning",
]

_LAZY = {
    "HabituatingFilter": "novelty.filter",
    "NoveltyDetector": "novelty.detector",
    "Clusterer": "novelty.clusterers.base",
    "Match": "novelty.clusterers.base",
    "Growth": "novelty.clusterers.base",
    "Synapse": "novelty.habituation.base",
    "KernelSpec": "novelty._component",
    "squared_distances": "novelty.distances",
    "SOM": "novelty.clusterers.som",
    "StanleySynapse": "novelty.habituation.stanley",
    "ModelFileError": "novelty.persistence",
    "FittedPartError": "novelty._component",
    "ScanRangeWarning": "novelty.filter",
}


_moved.install()   # module paths that moved keep working, with a FutureWarning

#: subpackages reachable as attributes after ``import novelty`` alone, imported on first use
_SUBPACKAGES = ("datasets", "sonar", "bench", "baselines", "clusterers", "habituation", "testing",
                "rules", "maps", "io", "tasks")


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    if name in _SUBPACKAGES:
        return importlib.import_module(f"novelty.{name}")  # which also sets the attribute
    raise AttributeError(f"module 'novelty' has no attribute {name!r}")


def make(name: str, **params: Any):
    """Build the detector registered as ``name`` with ``params``.

    ``make("hsom")`` is the paper's detector; ``make("habituating",
    clusterer="som", synapse="stanley", **params)`` composes any clusterer
    and synapse by name, each parameter going to the part that takes it.
    """
    return _registries.detectors.make(name, **params)


def available(kind: str | None = None) -> dict:
    """Every registered name with its one-line description, by kind.

    ``kind`` is one of ``"detectors"``, ``"clusterers"``, ``"synapses"``,
    ``"datasets"``; without it, all of them.
    """
    registries = {f"{k}s": _registries.of_kind(k) for k in _registries.KINDS}
    if kind is not None:
        if kind not in registries:
            raise ValueError(f"Unknown kind {kind!r}; expected one of {', '.join(registries)}.")
        return plain_descriptions(registries[kind])
    return {k: plain_descriptions(r) for k, r in registries.items()}


def load(path):
    """Read a detector saved with ``detector.save(path)`` (safe: no pickle)."""
    # deferred: persistence imports numpy; ``import novelty`` stays light
    from .persistence import load as _load

    return _load(path)


def register_clusterer(name: str, obj: Any = None, *, description: str | None = None, replace: bool = False):
    """Register a :class:`Clusterer` subclass under ``name`` (usable as a decorator)."""
    return _registries.clusterers.register(name, obj, description=description, replace=replace)


def register_synapse(name: str, obj: Any = None, *, description: str | None = None, replace: bool = False):
    """Register a :class:`Synapse` subclass under ``name`` (usable as a decorator)."""
    return _registries.synapses.register(name, obj, description=description, replace=replace)


def register_detector(name: str, obj: Any = None, *, description: str | None = None, replace: bool = False):
    """Register a detector class or factory under ``name`` (usable as a decorator)."""
    return _registries.detectors.register(name, obj, description=description, replace=replace)
