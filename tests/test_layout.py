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
- The library says what it does: no module of ``novelty/`` speaks of a study's
  selections, rounds or seeds (a docstring cites ``studies/<name>/`` instead,
  CHANGELOG.md keeps how the defaults changed) or quotes a timing (the
  performance guide keeps them); and a study reads the library through its
  public names only.
"""

import ast
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
    for top in ("novelty", "tests", "docs", "benchmarks", "studies", "examples"):
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



# ------------------------------------------------------------ the library and its studies
_NUM = r"\d(?:[\d.,]*\d)?"
_SPAN = rf"{_NUM}(?:\s*(?:-|–|to)\s*{_NUM})?"
#: a study speaking of itself: its selections and their rounds, its seed sets, a default's history
STUDY = re.compile(r"""
    \b(?:first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|\d+(?:st|nd|rd|th))\s+selection\b
  | \bselection(?:'s)?\s+(?:seeds?|runs?|rounds?|rule)\b
  | \brounds?\s+\d+\b
  | \bseeds?\s+\d+\s*(?:-|–)\s*\d+\b
  | \b(?:development|reported|guard)(?:'s)?\s+seeds\b
  | \bdefaults?\s+(?:was|were)\b
  | benchmarks/selection\b
""", re.IGNORECASE | re.VERBOSE)
#: a quoted timing: how long the code took, a rate of scans, how much faster or slower it ran
TIMING = re.compile(rf"""
    {_SPAN}\s*(?:ns|us|µs|μs|ms)\b
  | {_SPAN}\s*(?:s|seconds?|min|minutes?)\s+(?:of\s+CPU|to\s+import|a\s+call|a\s+scan|per\s+call|per\s+scan)\b
  | \b(?:two|three|a\s+few|several)\s+(?:seconds|minutes)\s+of\s+CPU\b
  | \b(?:took|takes|take|cost|costs|spent|spends|ran\s+in|runs\s+in)\s+(?:about\s+|up\s+to\s+)?{_SPAN}\s*(?:s|seconds?|min|minutes?)\b
  | \bmeasured:?\s+{_SPAN}\s*(?:s|seconds?)\b
  | \bscans?\s+(?:a|per)\s+second\b | \bscans/s\b
  | {_NUM}\s*(?:x|×)\s+(?:faster|slower|longer|its\s+warm)
  | {_NUM}\s*%\s+(?:faster|slower|longer|shorter|more\s+slowly)
  | \b(?:a\s+(?:fifth|third|quarter|half)|twice|{_NUM}\s+times)\s+(?:faster|slower|longer|more\s+slowly)
""", re.IGNORECASE | re.VERBOSE)
#: (a file of novelty/, what the patterns find in it or None for every finding): why it stays
ALLOWED = {
    ("sonar/robot.py", "15 ms"): "the simulated Nomad's sonar fires for about 15 ms: a property of the robot, "
                                 "not a timing of the code",
}


@pytest.mark.parametrize("text, found", [
    ("(The default was 3 until the seventh selection.)", "default was"),
    ("chosen by the sixth selection on development seeds", "sixth selection"),
    ("on the selection seeds 5-9", "selection seeds"), ("seeds 100-104 of the objects tasks", "seeds 100-104"),
    ("the guard's seeds", "guard's seeds"), ("rounds 4-5 had F = 0", "rounds 4"), ("round 6", "round 6"),
    ("the 7th selection", "7th selection"),
    ("Scorers for scikit-learn's model selection, on the novelty scale", None), ("a round robot", None),
    ("rounds once", None), ("all round", None), ("seeds 0 to N-1", None), ("--seeds 3", None),
    ("the default is 0.5", None),
])
def test_the_study_pattern(text, found):
    match = STUDY.search(text)
    assert (match.group(0) if match else None) == found


@pytest.mark.parametrize("text, found", [
    ("1.4 ms for hsom, against 0.34 ms", "1.4 ms"), ("cost 15-30 us of every engine", "15-30 us"),
    ("scipy.linalg takes 0.35 s to import", "takes 0.35 s"), ("(2-3 s to import)", "2-3 s to import"),
    ("about 9 ms of CPU", "9 ms"), ("about two minutes of CPU the first time", "two minutes of CPU"),
    ("a 10,000-scan first batch took 20 s", "took 20 s"), ("(measured: 0.05 s and 0.6 s)", "measured: 0.05 s"),
    ("3,694,113 scans a second", "scans a second"), ("about 1.5x faster", "1.5x faster"),
    ("6.3x its warm time", "6.3x its warm"), ("about 11 % faster", "11 % faster"),
    ("about a fifth slower", "a fifth slower"),
    ("tau = 3.33", None), ("a controller's command (~0.5 s correlation)", None), ("a laser at 10 Hz", None),
    ("tf2's default cache is 10 s", None), ('f"{_cpu_seconds():.0f} s of CPU time"', None),
    ("a visit ends after 2 s away", None), ("every 0.25 m", None), ("slower than one more vector", None),
])
def test_the_timing_pattern(text, found):
    match = TIMING.search(text)
    assert (match.group(0) if match else None) == found


def _library_findings() -> dict:
    """``{(file, finding): line}`` for every study word and quoted timing in novelty/."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for pattern in (STUDY, TIMING):
                for m in pattern.finditer(line):
                    found.setdefault((rel, m.group(0)), f"novelty/{rel}:{i}: {line.strip()}")
    return found


def test_the_library_speaks_of_no_study_and_quotes_no_timing():
    found = _library_findings()
    kept = {key for key in found if key in ALLOWED or (key[0], None) in ALLOWED}
    stray = sorted(line for key, line in found.items() if key not in kept)
    assert not stray, ("a docstring says what the code does and cites its study in one line (studies/<name>/); "
                       "a default's history goes to CHANGELOG.md, a timing to docs/guide/performance.md:\n"
                       + "\n".join(stray))
    stale = [key for key in ALLOWED if not any(k == key or (key[1] is None and k[0] == key[0]) for k in found)]
    assert not stale, f"allowed findings no longer there (remove them from ALLOWED): {stale}"


def _private_reads(path: Path) -> set[str]:
    """The library's private names ``path`` imports (a module or a name that starts with ``_``) and the
    private attributes it reads on anything but the study's own modules (``from . import scores``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    own = {a.asname or a.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.level
           for a in node.names}

    def private(name: str) -> bool:
        return name.startswith("_") and not name.startswith("__")

    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(part for a in node.names if a.name.split(".")[0] == "novelty"
                         for part in a.name.split(".") if private(part))
        elif isinstance(node, ast.ImportFrom) and not node.level and (node.module or "").split(".")[0] == "novelty":
            found.update(part for part in node.module.split(".") if private(part))
            found.update(a.name for a in node.names if private(a.name))
        elif isinstance(node, ast.Attribute) and private(node.attr):
            if not (isinstance(node.value, ast.Name) and node.value.id in own):
                found.add(node.attr)
    return found


def test_the_private_name_finder(tmp_path):
    script = tmp_path / "study.py"
    script.write_text("import novelty._kernels.state\n"
                      "from novelty.maps.cells import _scan, WorldCells\n"
                      "from novelty.maps import habituating_map\n"
                      "from . import scores\n"
                      "det = habituating_map()\n"
                      "det._cells, det.clusterer_.passes_, scores._rows, det.__class__\n", encoding="utf-8")
    assert _private_reads(script) == {"_kernels", "_scan", "_cells"}
    assert _private_reads(Path(__file__).parent / "printed.py") == set()


def test_studies_read_the_library_through_its_public_names():
    scripts = sorted((ROOT / "studies").rglob("*.py"))
    assert scripts, "no study scripts found"
    reads = {path.relative_to(ROOT).as_posix(): _private_reads(path) for path in scripts}
    private = {rel: sorted(names) for rel, names in reads.items() if names}
    assert not private, f"study scripts reading the library's private names (use or add a public API): {private}"
