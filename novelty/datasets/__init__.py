"""Datasets and novelty tasks, by name.

``available()`` lists them with a one-line description; ``load(name, **options)``
builds one. Third-party datasets register through the entry-point group
``novelty.datasets``.

Built in:

- the paper's environments, simulated (:mod:`novelty.sonar`): ``paper-a``,
  ``paper-a-star``, ``paper-b``, ``paper-c``, ``paper-control``
  (``run=0, seed=0, runs=1``);
- tasks from the paper's experiments: ``paper-a-to-a-star``, ``paper-a-to-b``,
  ``paper-a-to-c`` (``seed=0, train_runs=3, test_runs=1``);
- inspection tasks on generated corridors: ``inspection`` (any
  ``difficulty``), ``inspection-easy``, ``inspection-medium``,
  ``inspection-hard`` (``seed=0, n_novelties=2, train_runs=3, test_runs=1,
  length=15.0``);
- exploration tasks, runs in order with every scan's tracked feature and its
  exposure count (:mod:`novelty.datasets.exploration`): ``exploration-tour``,
  ``exploration-open-door``, ``exploration-patrol``, ``exploration-irregular``,
  ``exploration-return``, ``exploration-moving``; from the Radish robot logs
  (:mod:`novelty.tasks.radish`, read from ``path=`` or ``$NOVELTY_DATA_DIR``):
  ``exploration-radish-intel``, ``exploration-radish-aces``,
  ``exploration-radish-csail``;
- virtual objects placed in a recording (:mod:`novelty.tasks.objects`):
  ``inspection-objects`` and ``exploration-objects`` for any recording with
  poses (``path=``, ``objects=`` a CSV or TOML file, or objects drawn by the
  seed), and the Radish logs' ``inspection-objects-radish-intel``,
  ``-aces``, ``-csail`` and ``exploration-objects-radish-intel``, ``-aces``,
  ``-csail``;
- real data, read from the user's files (``path=`` or ``$NOVELTY_DATA_DIR``):
  ``uci-wall-following``, ``uci-wall-following-novelty``, ``uci-sonar``,
  ``uci-sonar-mines``;
- the user's own scans, a CSV or NPZ file: ``files`` (``path=``, with
  ``columns``, ``label``, ``time``, and ``train_rows``, ``split`` or
  ``test_path``; see :mod:`novelty.datasets.files`).

``registry`` is :data:`novelty.registry.datasets`, beside the registries of
the other kinds of component.
"""

from __future__ import annotations

from .._markup import plain_descriptions
from ..data import Dataset
from ..registry import datasets as registry

__all__ = ["Dataset", "registry", "available", "load", "register"]


def available() -> dict:
    """Every dataset name with its one-line description."""
    return plain_descriptions(registry)


def load(name: str, **options):
    """Build the dataset registered as ``name``."""
    return registry.make(name, **options)


def register(name: str, obj=None, *, description: str | None = None, replace: bool = False):
    """Register a dataset factory under ``name`` (usable as a decorator)."""
    return registry.register(name, obj, description=description, replace=replace)
