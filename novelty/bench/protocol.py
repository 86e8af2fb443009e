"""A protocol: how a cell trains and scores a detector, and how its results are read.

Each protocol is one sub-package of :mod:`novelty.bench` exposing one
:class:`Protocol` as ``PROTOCOL``:

- ``holdout`` (:mod:`novelty.bench.holdout`): train on the familiar route,
  freeze, score the test part;
- ``exploration`` (:mod:`novelty.bench.exploration`): every scan scored, then
  learned, in order.

A protocol is chosen by name (:func:`get_protocol`); the cell, the runner,
the summary and the plots ask it, never test its name.

Shares its name with ``novelty/reproduce/protocol.py``: the paper's protocol and the benchmark's
protocols are two things of one name.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

__all__ = ["Protocol", "get_protocol", "PROTOCOL_NAMES"]

#: the built-in protocols: name -> the sub-package that defines it
_BUILTIN = {"holdout": "novelty.bench.holdout", "exploration": "novelty.bench.exploration"}
#: their names, in the order the documentation lists them
PROTOCOL_NAMES = tuple(_BUILTIN)


@dataclass(frozen=True)
class Protocol:
    """Everything the harness needs to know of one protocol.

    Attributes
    ----------
    name : str
    evaluate : callable
        ``evaluate(cell) -> (row, arrays)``: the metrics of one cell and its
        per-scan arrays (kept for plots and the paired bootstrap).
    columns : tuple of str
        The metric columns of a cell: identical across backends and reruns.
    metric : str
        The column detectors are ranked and compared by.
    metric_name : str
        How tables and plots name it.
    table : callable
        ``table(rows) -> str``: the table printed at the end of a run.
    summary : callable
        ``summary(rows) -> list of str``: the protocol's own sections of
        ``summary.md`` (markdown lines).
    plots : callable
        ``plots(rows, arrays, out) -> list of Path``: the protocol's own
        figures (``arrays(cell_id)`` reads a cell's arrays).
    """

    name: str
    evaluate: Callable[..., tuple[dict, dict]]
    columns: tuple[str, ...]
    metric: str
    metric_name: str
    table: Callable[[Sequence[dict]], str]
    summary: Callable[[Sequence[dict]], list[str]]
    plots: Callable[..., list[Path]]


def get_protocol(name: str) -> Protocol:
    """The protocol called ``name`` (``"holdout"`` or ``"exploration"``)."""
    if name not in _BUILTIN:
        raise ValueError(f"Unknown protocol {name!r}; expected one of {', '.join(PROTOCOL_NAMES)}.")
    return importlib.import_module(_BUILTIN[name]).PROTOCOL
