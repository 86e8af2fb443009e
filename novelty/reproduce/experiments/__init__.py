"""Experiments that explain why Table 1 of Marsland et al. (2000) does not reproduce.

Each experiment runs in seconds to a minute and writes a table (CSV and
markdown) and a figure; ``novelty reproduce --experiment NAME`` runs one,
``--experiment all`` runs them all and can fill the generated blocks of
``docs/reproduction.md`` (``--report``). What each one varies is ours, not
the paper's, unless it says otherwise:

- ``table1``: the paper's protocol on every seed, Table 1 beside ours, and
  each of the paper's claims checked seed by seed;
- ``synthetic``: the paper's map on corridors of K exactly repeating
  perceptions and of one perception with small noise;
- ``ablations``: the simulated corridor A with one switch of the simulator
  changed at a time;
- ``sensitivity``: options of the map that are not in the paper (a
  neighbour learning rate of its own; exact integration of the synapse);
- ``maxima``: which of Table 1's maxima each integration of the synapse can
  reach, and with how many winner and neighbour steps.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import TextIO

from . import summary
from ._common import markdown_table, reporting, write_csv

__all__ = ["names", "run_experiment", "write_summary"]

_MODULES = ("table1", "synthetic", "ablations", "sensitivity", "maxima")


def names() -> list[str]:
    """The experiments' names, in the order ``all`` runs them."""
    return list(_MODULES)


def run_experiment(name: str, out, seeds=range(10), jobs: int = 1, progress: TextIO | None = None):
    """Run experiment ``name``; write its table and figure to ``out``; return its :class:`Result`.

    ``progress``: a stream (e.g. ``sys.stderr``) told of each finished step
    (a line, or a tqdm bar on a terminal); None: silent.
    """
    if name not in _MODULES:
        raise ValueError(f"Unknown experiment {name!r}; known: {', '.join(_MODULES)}, all.")
    module = importlib.import_module(f"{__name__}.{name}")
    with reporting(name, progress):
        result = module.run(Path(out), seeds=seeds, jobs=jobs)
    result.write(Path(out))
    return result


def write_summary(results: dict, out) -> str:
    """``summary.csv`` and ``summary.md`` from the results of every experiment; returns the markdown."""
    rows = summary.rows(results)
    text = markdown_table(rows) + "\n"
    write_csv(rows, Path(out) / "summary.csv")
    (Path(out) / "summary.md").write_text(text, encoding="utf-8")
    return text
