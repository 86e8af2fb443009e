"""Datasets and novelty tasks, by name.

``available()`` lists them with a one-line description; ``load(name, **options)``
builds one. Third-party datasets register through the entry-point group
``novelty.datasets``.
"""

from __future__ import annotations

from ..registry import Registry
from .base import Dataset

__all__ = ["Dataset", "registry", "available", "load", "register"]

registry = Registry("dataset", group="novelty.datasets", builtins={})


def available() -> dict:
    """Every dataset name with its one-line description."""
    return dict(registry.descriptions())


def load(name: str, **options):
    """Build the dataset registered as ``name``."""
    return registry.make(name, **options)


def register(name: str, obj=None, *, description: str | None = None, replace: bool = False):
    """Register a dataset factory under ``name`` (usable as a decorator)."""
    return registry.register(name, obj, description=description, replace=replace)
