"""``novelty list``: every registered detector, clusterer, synapse and dataset."""

from __future__ import annotations

from .._markup import plain_text
from ..registry import of_kind
from ._common import add_command

KINDS = ("detectors", "clusterers", "synapses", "datasets")


def add_parser(subparsers):
    parser = add_command(
        subparsers, "list", "list detectors, clusterers, synapses, datasets and tasks",
        "List every registered component by kind, with its one-line description. Plugins "
        "installed through the novelty.* entry-point groups are listed too.",
        ["novelty list", "novelty list detectors", "novelty list datasets"],
    )
    parser.add_argument("kind", nargs="?", choices=KINDS, help="list only this kind")
    return parser


def _describe(registry, name: str) -> str:
    try:
        return plain_text(registry.describe(name) or "")
    except Exception as exc:  # noqa: BLE001 - a broken plugin must not hide the others
        return f"(cannot be loaded: {type(exc).__name__}: {' '.join(str(exc).split())})"


def _loop(kind: str, registry, name: str) -> str:
    """For a clusterer or synapse: whether it learns compiled inside a habituating filter."""
    if kind not in ("clusterers", "synapses"):
        return ""
    try:
        declared = "_kernel" in vars(registry.get(name))
    except Exception:  # noqa: BLE001 - described as broken above
        return ""
    return " [compiled]" if declared else " [reference loop: declares no compiled steps]"


def run(args) -> int:
    kinds = [args.kind] if args.kind else list(KINDS)
    for i, kind in enumerate(kinds):
        registry = of_kind(kind[:-1])
        names = registry.names()
        title = "datasets and tasks" if kind == "datasets" else kind
        if i:
            print()
        print(f"{title.capitalize()} ({len(names)}):")
        width = max((len(n) for n in names), default=0)
        for name in names:
            print(f"  {name.ljust(width)}  {_describe(registry, name)}{_loop(kind, registry, name)}")
        if not names:
            print("  (none registered)")
        if registry.elsewhere:
            print(f"  Not registered, run by 'novelty bench' by name: {', '.join(registry.elsewhere)} (River's "
                  "anomaly detectors, extra river; no model file holds them).")
    return 0
