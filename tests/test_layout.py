"""The repository's layout: what a reader of the code meets.

- No tracker numbers ("issue 7", "#12") in code, tests, docs or benchmarks: a
  reader of the code cannot follow them.
- Tests mirror the package: ``tests/<subpackage>/test_<module>.py`` tests
  ``novelty/<subpackage>/<module>.py``; the few that test across modules are
  named in :data:`ACROSS`.
- No import cycle among novelty's modules, counting the imports inside
  functions too (an import moved into a function hides a cycle from Python,
  not from a reader), and none among its subpackages, nor among the
  readers' layers (novelty.io's folders).
- Each layer of the readers stands on at most four import levels.
"""

import importlib.util
import re
from collections import defaultdict
from pathlib import Path

import pytest

import novelty

ROOT = Path(novelty.__file__).resolve().parents[1]
PACKAGE = ROOT / "novelty"

# "issue 7", "issues #7", "PR 12", "gh-12", "#12"; not a colour ("#d62728", "#222222")
TRACKER = re.compile(r"\b(?:issue|pull request|PR|ticket)s?\s*#?\s*\d+|(?<![\w&#/])#\d{1,5}(?![0-9a-fA-F])|\bgh-\d+",
                     re.IGNORECASE)
TEXT = {".py", ".md", ".toml", ".txt", ".rst", ".cfg", ".yml", ".yaml"}


def _text_files():
    for top in ("novelty", "tests", "docs", "benchmarks", "examples"):
        for path in sorted((ROOT / top).rglob("*")):
            rel = path.relative_to(ROOT).parts
            if path.suffix in TEXT and not {"_build", "__pycache__"} & set(rel) and rel[:2] != ("docs", "api"):
                yield path
    yield ROOT / "README.md"


@pytest.mark.parametrize("text, found", [
    ("see issue 7", "issue 7"), ("Issues #12 and", "Issues #12"), ("PR 3", "PR 3"), ("(#45)", "#45"),
    ("gh-101", "gh-101"), ('colour "#d62728"', None), ('"#222222"', None), ("x = 3  # 10 scans", None),
    ("tissue 7", None),
])
def test_the_tracker_pattern(text, found):
    match = TRACKER.search(text)
    assert (match.group(0) if match else None) == found


def test_no_tracker_numbers():
    hits = [f"{path.relative_to(ROOT)}:{i}: {line.strip()}"
            for path in _text_files() if path.is_file()
            for i, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1)
            if TRACKER.search(line) and path != Path(__file__).resolve()]  # this file shows examples
    assert not hits, "tracker numbers mean nothing to a reader of the code:\n" + "\n".join(hits)


# ------------------------------------------------------------------ imports
# The import graph is read as benchmarks/import_levels.py reads it (that script prints it per layer).
_spec = importlib.util.spec_from_file_location("import_levels", ROOT / "benchmarks" / "import_levels.py")
import_levels = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(import_levels)


def _modules() -> dict[str, Path]:
    """Every module of the package by dotted name (a package by its own name)."""
    return import_levels.modules(PACKAGE)


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one node (Tarjan's algorithm)."""
    index, low, stack, on_stack, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def _graph() -> dict[str, set[str]]:
    return import_levels.graph(PACKAGE)


def test_the_cycle_finder():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_the_import_graph_sees_imports_in_functions():
    graph = _graph()
    assert "novelty.registry" in graph["novelty.filter"]  # at the top of the module
    assert "novelty.persistence" in graph["novelty"]       # inside novelty.load()


def test_no_import_cycle_among_modules():
    cycles = _cycles(_graph())
    assert not cycles, f"modules that import each other (directly or around a loop): {cycles}"


def test_no_import_cycle_among_subpackages():
    def top(module):
        return ".".join(module.split(".")[:2])

    edges: dict[str, set[str]] = defaultdict(set)
    for module, imported in _graph().items():
        edges[top(module)].update(top(m) for m in imported if top(m) not in (top(module), "novelty"))
    cycles = _cycles(edges)
    assert not cycles, f"subpackages that import each other: {cycles}"


def test_no_import_cycle_among_the_readers_layers():
    def layer(module):
        return ".".join(module.split(".")[:3])

    edges: dict[str, set[str]] = defaultdict(set)
    for module, imported in _graph().items():
        if module.startswith("novelty.io."):
            edges[layer(module)].update(layer(m) for m in imported
                                        if m.startswith("novelty.io.") and layer(m) != layer(module))
    cycles = _cycles(edges)
    assert not cycles, f"layers of novelty.io that import each other: {cycles}"


def test_the_levels_of_a_layer_count_its_own_imports_only():
    edges = {"a": {"b", "x"}, "b": {"c"}, "c": set(), "d": {"c"}}
    assert import_levels.levels({"a", "b", "c", "d"}, edges) == {"a": 3, "b": 2, "c": 1, "d": 2}
    assert import_levels.longest_chains({"a", "b", "c", "d"}, edges, {"a": 3, "b": 2, "c": 1, "d": 2}) == [
        ["a", "b", "c"]]


@pytest.mark.parametrize("layer, found", sorted(import_levels.layers(PACKAGE, "novelty.io").items()))
def test_each_layer_of_the_readers_stands_on_at_most_four_levels(layer, found):
    assert found["levels"] <= import_levels.MAX_LEVELS, (
        f"{layer} stands on {found['levels']} levels: {' -> '.join(found['chains'][0])}")


# --------------------------------------------------------------- test files
#: test files that test across modules, not one module each
ACROSS = {
    "test_docs.py": "the documentation pages' examples",
    "test_readme.py": "the README's examples",
    "test_tables.py": "the results tables of the documents against benchmarks/results/ and the suites",
    "test_maps_diagnosis.py": "benchmarks/maps_diagnosis.py: its split of the first-encounter AUC's shortfall",
    "test_maps_guard_trace.py": "benchmarks/maps_guard_trace.py: each guard scan traced to its most novel cell",
    "test_maps_round4.py": "benchmarks/maps_round4.py: the scores of the habituating-map selections",
    "test_learning_answer.py": "benchmarks/learning_answer.py: the scores and the decision of the learning answer's rule",
    "test_guard_margins.py": "benchmarks/guard_margins.py: each guard mean's interval over its seeds",
    "test_perf_compare.py": "benchmarks/perf_compare.py: two revisions timed alternately",
    "test_layout.py": "this file: the layout of the repository",
    "test_sklearn_compat.py": "scikit-learn's estimator checks on every registered component",
    "test_plugin.py": "a third-party plugin package, listed and benchmarked",
    "baselines/test_baseline_checks.py": "the estimator and conformance checks on other configurations",
    "fuzz/test_detectors.py": "every registered detector against hostile input",
    "fuzz/test_files.py": "hostile save targets, suite files and standard input",
    "tasks/objects/test_bags.py": "the tasks read from a bag (novelty.tasks.objects, novelty.tasks.recordings) with a laser's mount",
    "tasks/objects/test_points.py": "the points input (novelty.io.scans.points) of the objects tasks' sweeps",
    "_kernels/test_hostile_state.py": "both engines against a hostile state of every pair (choice, state, the drivers)",
}


def test_every_test_file_is_named_after_the_module_it_tests():
    modules = set(_modules())
    tests = ROOT / "tests"
    stray = []
    for path in sorted(tests.rglob("test_*.py")):
        rel = path.relative_to(tests)
        if rel.as_posix() in ACROSS:
            continue
        package = ".".join(("novelty", *rel.parts[:-1]))
        stem = rel.stem[len("test_"):]
        candidates = {f"{package}.{stem}", f"{package}._{stem}", f"{package}.{stem}_"}
        if stem == "init":
            candidates.add(package)
        if not candidates & modules:
            stray.append(rel.as_posix())
    assert not stray, f"test files not named after a module of the package (or listed in ACROSS): {stray}"



# ------------------------------------------------------------- the house, as the guides draw it
#: the pages that name the package's folders and modules
HOUSE_PAGES = ("docs/guide/layout.md", "docs/guide/engine.md")
#: a path of the repository written in a page: under one of its top folders, a folder or a module
PATH = re.compile(r"(?<![\w./<-])((?:novelty|tests|studies|benchmarks|docs|examples)/[\w./-]*)")


def _named_paths(page: str) -> set[str]:
    found = set()
    for match in PATH.finditer((ROOT / page).read_text(encoding="utf-8")):
        path = match.group(1).rstrip(".,:;")
        if not path.endswith("/") and "." not in path.rsplit("/", 1)[-1]:
            continue   # neither a folder (written with its slash) nor a file: a module path in prose
        found.add(path)
    return found


def test_the_path_pattern_finds_folders_and_files_not_placeholders():
    text = "in `novelty/io/<format>/`, `novelty/io/scans/` and novelty/io/scans/sweeps.py, tests/io/, novelty.io"
    assert {m.group(1) for m in PATH.finditer(text)} == {"novelty/io/", "novelty/io/scans/",
                                                          "novelty/io/scans/sweeps.py", "tests/io/"}


@pytest.mark.parametrize("page", HOUSE_PAGES)
def test_every_folder_and_module_a_guide_names_exists(page):
    missing = sorted(path for path in _named_paths(page) if not (ROOT / path).exists())
    assert _named_paths(page), f"{page} names no path"
    assert not missing, f"{page} names paths that do not exist: {missing}"


def test_the_house_names_every_folder_of_the_package_and_of_the_readers():
    named = _named_paths("docs/guide/layout.md")
    text = (ROOT / "docs/guide/layout.md").read_text(encoding="utf-8")
    folders = sorted(p.relative_to(ROOT).as_posix() + "/" for p in PACKAGE.iterdir()
                     if (p / "__init__.py").exists())
    readers = sorted(p.name + "/" for p in (PACKAGE / "io").iterdir() if (p / "__init__.py").exists())
    assert not [f for f in folders if f not in named and f.split("/", 1)[1] not in text], folders
    assert not [r for r in readers if f"  {r}" not in text], readers
