"""The package's import structure, read from the source: per layer, its levels, arrows and longest chains.

A *layer* is a package's folder: the modules directly in it (its
``__init__`` apart, which is the layer's door, not one of its floors). A
module stands one level above everything it imports from its own layer:
level 1 imports nothing of its layer, level 2 imports level-1 modules only,
and so on; a layer's height is its highest level. *Arrows* count imports
between two modules, inside the layer and out of it (to other layers of the
package). A *longest chain* is a path of imports down the layer's levels.

Imports are read from the abstract syntax tree, in functions too (an import
moved into a function hides an arrow from Python, not from a reader); those
under ``if TYPE_CHECKING:`` are not run and do not count.
``tests/test_layout.py`` reads the same graph for its checks (no cycles; the
readers' layers at most :data:`MAX_LEVELS` high).

    python benchmarks/import_levels.py               # every layer of novelty/
    python benchmarks/import_levels.py novelty.io    # novelty.io and the layers under it
    python benchmarks/import_levels.py --modules novelty.io.scans   # and each module's level
    python benchmarks/import_levels.py --whole novelty.io           # novelty.io and all below it as one layer
"""

from __future__ import annotations

import argparse
import ast
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "novelty"
#: the most levels a layer of the readers (novelty.io's folders) stands on
MAX_LEVELS = 4


def modules(package: Path = PACKAGE) -> dict[str, Path]:
    """Every module of the package by dotted name (a package by its own name)."""
    out = {}
    for path in sorted(package.rglob("*.py")):
        parts = list(path.relative_to(package.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def imported(name: str, path: Path, known) -> set[str]:
    """The package's modules that ``name`` imports anywhere in its file, in functions too.

    ``from package import submodule`` imports the submodule; ``from module
    import name`` the module; imports under ``if TYPE_CHECKING:`` do not count.
    """
    top = name.split(".")[0]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()

    def nearest(target):
        while target not in known and "." in target:
            target = target.rpartition(".")[0]
        return target if target in known and target != name else None

    def visit(node):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                continue
            if isinstance(child, ast.Import):
                found.update(nearest(a.name) for a in child.names if a.name.split(".")[0] == top)
            elif isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package.split(".")[: len(package.split(".")) - child.level + 1]
                    source = ".".join(base + ([child.module] if child.module else []))
                else:
                    source = child.module or ""
                if source.split(".")[0] == top:
                    for alias in child.names:
                        sub = f"{source}.{alias.name}"
                        found.add(nearest(sub if sub in known else source))
            visit(child)

    visit(ast.parse(path.read_text(encoding="utf-8")))
    return found - {None}


def graph(package: Path = PACKAGE) -> dict[str, set[str]]:
    """Each module's imports of the package's modules."""
    known = modules(package)
    return {name: imported(name, path, known) for name, path in known.items()}


def layer_of(module: str, packages: set[str]) -> str:
    """The package whose folder holds ``module`` (a package's ``__init__`` is its own layer's door)."""
    return module if module in packages else module.rpartition(".")[0]


def packages_of(known: dict[str, Path]) -> set[str]:
    return {name for name, path in known.items() if path.name == "__init__.py"}


def levels(members: set[str], edges: dict[str, set[str]]) -> dict[str, int]:
    """Each member's level among ``members`` (1 + the highest level it imports; 1 for none)."""
    out: dict[str, int] = {}

    def level(m, seen=()):
        if m not in out:
            if m in seen:
                raise ValueError(f"an import cycle through {m}")
            below = [level(d, seen + (m,)) for d in edges.get(m, ()) if d in members]
            out[m] = 1 + max(below, default=0)
        return out[m]

    for m in sorted(members):
        level(m)
    return out


def longest_chains(members: set[str], edges: dict[str, set[str]], height: dict[str, int]) -> list[list[str]]:
    """The import paths down every level of the layer, from each of its top modules (first path of each)."""
    def down(m):
        nxt = sorted(d for d in edges.get(m, ()) if d in members and height[d] == height[m] - 1)
        return [m] + (down(nxt[0]) if nxt else [])

    top = max(height.values(), default=0)
    return [down(m) for m in sorted(members) if height[m] == top]


def layers(package: Path = PACKAGE, under: str = "", whole: bool = False) -> dict[str, dict]:
    """Per layer: its modules' levels, its height, its arrows inside and out, its longest chains.

    ``whole``: the package ``under`` and everything below it as one layer.
    """
    known = modules(package)
    edges = graph(package)
    packages = packages_of(known)
    found = defaultdict(set)
    for name in known:
        if name not in packages:
            found[under if whole and name.startswith(under + ".") else layer_of(name, packages)].add(name)
    if whole:
        packages = {under}
    out = {}
    for layer in sorted(packages):
        if under and not (layer == under or layer.startswith(under + ".")):
            continue
        members = found.get(layer, set())
        height = levels(members, edges)
        inside = sum(len(edges[m] & members) for m in members)
        outside = sum(len(edges[m] - members - {layer}) for m in members)
        out[layer] = {"modules": len(members), "levels": max(height.values(), default=0), "inside": inside,
                      "outside": outside, "height": height, "chains": longest_chains(members, edges, height)}
    return out


def report(found: dict[str, dict], show_modules: bool = False) -> str:
    lines = [f"{'layer':<34} {'modules':>7} {'levels':>6} {'arrows in':>9} {'arrows out':>10}  longest chain"]
    for layer, row in found.items():
        short = [m.rpartition(".")[2] for m in row["chains"][0]] if row["chains"] else []
        more = f" (+{len(row['chains']) - 1} more)" if len(row["chains"]) > 1 else ""
        lines.append(f"{layer:<34} {row['modules']:>7} {row['levels']:>6} {row['inside']:>9} {row['outside']:>10}  "
                     f"{' -> '.join(short)}{more}")
        if show_modules:
            for m, level in sorted(row["height"].items(), key=lambda kv: (-kv[1], kv[0])):
                lines.append(f"    {level:>2}  {m}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("under", nargs="?", default="", help="a package: only it and the layers under it")
    parser.add_argument("--modules", action="store_true", help="each module's level too")
    parser.add_argument("--whole", action="store_true", help="the package named and all below it as one layer")
    args = parser.parse_args(argv)
    if args.whole and not args.under:
        parser.error("--whole needs a package")
    print(report(layers(under=args.under, whole=args.whole), args.modules))
    return 0


if __name__ == "__main__":
    sys.exit(main())
