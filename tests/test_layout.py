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
- Private names stay with their owner: no module outside the habituating
  filter (``novelty/filter.py``, ``novelty/_filter/``) uses the filter's
  private names, and no private name is imported from outside the package that
  holds it.
- A module name used twice in ``novelty/`` says why, in the module and in
  :data:`SHARED_NAMES`.
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
    "rosnode/test_guide.py": "the live-robot guide's session, run against a real ROS master",
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


# ------------------------------------------------------------- names that say where they live
#: module and package names used more than once in novelty/, and why each may be: every module of such a
#: name says so in its docstring ("shares its name with ...")
SHARED_NAMES = {
    "base": "each kind of component has its base classes beside its modules: clusterers/base.py, habituation/base.py",
    "_common": "a package's private helpers shared by its modules: cli/_common.py, reproduce/experiments/_common.py",
    "metrics": "each benchmark protocol's package holds its metrics, plots and summary (bench/holdout/, "
               "bench/exploration/); novelty/metrics.py is the users' ROC AUC of novelty scores",
    "plots": "each benchmark protocol's package holds its metrics, plots and summary",
    "summary": "each benchmark protocol's package holds its metrics, plots and summary; bench/reports/ and "
               "reproduce/experiments/ summarise a run of theirs",
    "exploration": "the exploration protocol (bench/exploration/, beside bench/holdout/) and its tasks "
                   "(tasks/exploration/)",
    "places": "places a robot meets again from its poses (tasks/places.py) and whether an object's place was seen "
              "before it appeared (tasks/objects/places.py, beside the other modules of objects)",
    "figures": "the figures of the paper's experiments (reproduce/) and of a benchmark's report (bench/reports/)",
    "protocol": "the paper's protocol (reproduce/) and the benchmark's protocols' interface (bench/)",
    "table1": "the paper's Table 1: its experiments (reproduce/experiments/) and its rows against the paper's "
              "(reproduce/)",
    "simulate": "the simulator (sonar/) and the command that runs it (cli/simulate.py: a command's module is named "
                "after the command)",
    "bench": "the benchmark (bench/) and the command that runs it (cli/bench.py)",
    "reproduce": "the paper's experiments (reproduce/) and the command that runs them (cli/reproduce.py)",
    "scans": "the scans a detector is given, checked (_validation/scans.py), and a recording's messages made "
             "scans (io/scans/)",
    "node": "the live node (rosnode/node.py) and the command that starts it (cli/node.py: a command's module is "
            "named after the command)",
    "reading": "how a recording is read (io/recording/reading.py, the Reading) and the live node's reading built "
               "on it (rosnode/reading.py)",
    "scoring": "the engines' batch scoring (_kernels/scoring.py) and the live node's scorer (rosnode/scoring.py)",
    "stats": "the benchmark's statistics (bench/stats/) and the live node's counts and latencies (rosnode/stats.py)",
}


def _names() -> dict[str, list[Path]]:
    """Each module or package name of novelty/ (a package by its folder) and where it is used."""
    found = defaultdict(list)
    for path in sorted(PACKAGE.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        if path.name == "__init__.py":
            if path.parent != PACKAGE:
                found[path.parent.name].append(path)
        else:
            found[path.stem].append(path)
    return found


def test_no_module_name_is_used_twice_without_a_reason():
    shared = {name: paths for name, paths in _names().items() if len(paths) > 1}
    unexplained = sorted(set(shared) - set(SHARED_NAMES))
    assert not unexplained, (f"module names used more than once (rename one, or give the reason in SHARED_NAMES and "
                             f"in each module): {[(n, [p.relative_to(PACKAGE).as_posix() for p in shared[n]]) for n in unexplained]}")
    assert not set(SHARED_NAMES) - set(shared), f"names no longer shared: {sorted(set(SHARED_NAMES) - set(shared))}"
    silent = [p.relative_to(PACKAGE).as_posix() for name in shared for p in shared[name]
              if "shares its name" not in (ast.get_docstring(ast.parse(p.read_text(encoding="utf-8"))) or "").lower()]
    assert not silent, f"modules whose docstring does not say why they share their name: {silent}"


# ------------------------------------------------------------- private names stay with their owner
#: the habituating filter: its class's module and its private parts' folder
FILTER = (PACKAGE / "filter.py", PACKAGE / "_filter")


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _library_files(*skip: Path):
    for path in sorted(PACKAGE.rglob("*.py")):
        if "__pycache__" not in path.parts and not any(path == s or s in path.parents for s in skip):
            yield path


def _filter_files():
    return [FILTER[0], *sorted(FILTER[1].glob("*.py"))]


def filter_private_names() -> set[str]:
    """The habituating filter's own private names: those its class defines that none of its base
    classes has (``_learn_raw``, ``_combine``, ...), and those its modules keep in its ``__dict__``
    (``vars(filter)["_engine"]``, ``self._calibration = ...``)."""
    from novelty.filter import HabituatingFilter

    names = {name for name in vars(HabituatingFilter) if _private(name)
             and not any(hasattr(base, name) for base in HabituatingFilter.__mro__[1:])}
    for path in _filter_files():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            key = None
            if isinstance(node, ast.Subscript) and _is_vars(node.value):
                key = node.slice
            elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and _is_vars(node.func.value)
                  and node.args):
                key = node.args[0]   # vars(x).get("_name"), .pop, .setdefault
            elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
                key = ast.Constant(node.attr)
            if isinstance(key, ast.Constant) and isinstance(key.value, str) and _private(key.value):
                names.add(key.value)
    return names


def _is_vars(node) -> bool:
    return isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "vars"


def private_uses(path: Path, names: set[str]) -> list[str]:
    """Where ``path`` reaches one of ``names`` on another object than its own (``self`` and
    ``cls`` are a class's own): ``x._name``, ``vars(x)["_name"]``, ``getattr(x, "_name")``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        name = None
        if isinstance(node, ast.Attribute) and node.attr in names:
            if not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
                name = node.attr
        elif isinstance(node, ast.Subscript) and _is_vars(node.value):
            name = getattr(node.slice, "value", None)
        elif isinstance(node, ast.Call) and node.args:
            reach = ((isinstance(node.func, ast.Attribute) and _is_vars(node.func.value))
                     or (isinstance(node.func, ast.Name) and node.func.id in ("getattr", "setattr", "hasattr",
                                                                               "delattr")))
            if reach:
                first = node.args[0] if _is_vars(getattr(node.func, "value", None)) else (
                    node.args[1] if len(node.args) > 1 else None)
                name = getattr(first, "value", None)
        if isinstance(name, str) and name in names:
            where = path.relative_to(ROOT).as_posix() if ROOT in path.parents else path.name
            found.append(f"{where}:{node.lineno} {name}")
    return found


def test_the_filter_private_name_finder(tmp_path):
    names = filter_private_names()
    assert {"_engine", "_calibration", "_parts_changed", "_parts_seen", "_learn_raw", "_combine",
            "_novelty_of", "_calibration_rule", "_current_engine"} <= names
    assert not {"_learn", "_novelty", "_start", "_check_state", "_rebuild_scratch"} & names  # the detector's hooks
    module = tmp_path / "module.py"
    module.write_text('def f(det):\n    det._combine(1)\n    vars(det)["_engine"] = 2\n    getattr(det, "_engine")\n'
                      'class E:\n    def g(self):\n        self._parts_seen = ()\n')
    assert sorted(use.split(" ")[1] for use in private_uses(module, names)) == ["_combine", "_engine", "_engine"]


def test_no_module_outside_the_filter_uses_its_private_names():
    names = filter_private_names()
    outside = [use for path in _library_files(*FILTER) for use in private_uses(path, names)]
    outside += [use for top in ("studies", "benchmarks", "examples") for path in sorted((ROOT / top).rglob("*.py"))
                for use in private_uses(path, names)]
    assert not outside, f"the habituating filter's private names used outside it (give them an owner): {outside}"


def _package_of(name: str, modules: dict[str, Path]) -> str:
    return name if modules[name].name == "__init__.py" else name.rpartition(".")[0]


def private_imports(modules: dict[str, Path]) -> list[str]:
    """Imports of a private name (a module or an object whose name starts with ``_``) from outside
    the package that holds it. A private name is its package's, for its modules and its
    subpackages' (``novelty._kernels`` is the whole library's; ``novelty.habituation._schedule``
    is ``novelty.habituation``'s; ``_lock_of`` of ``novelty/detector.py`` is ``novelty``'s)."""
    found = []
    for name, path in modules.items():
        here = _package_of(name, modules)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = here.split(".")[: len(here.split(".")) - node.level + 1] if node.level else []
                source = ".".join(base + ([node.module] if node.module else []))
                paths = [source] + [f"{source}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                paths = [a.name for a in node.names]
            else:
                continue
            for dotted in paths:
                parts = dotted.split(".")
                private = [i for i, part in enumerate(parts) if i and _private(part)]
                if parts[0] != "novelty" or not private:
                    continue
                holder = ".".join(parts[:private[0]])   # the module or package the private name is in
                owner = _package_of(holder, modules) if holder in modules else holder
                if here != owner and not here.startswith(owner + "."):
                    found.append(f"{name}:{node.lineno} {dotted}")
                    break   # an import statement counted once
    return found


def test_the_private_import_finder(tmp_path):
    files = {"__init__.py": "", "_k.py": "", "a/__init__.py": "", "a/x.py": "", "a/_y.py": "",
             "b/__init__.py": "", "a/c/__init__.py": "",
             "b/z.py": "from ..a import _y\nfrom ..a.x import _f, g\nfrom .._k import h\nimport novelty.a._y\n",
             "a/c/w.py": "from .. import _y\nfrom ..x import _f\nfrom ..._k import h\n"}
    for rel, text in files.items():
        (tmp_path / "novelty" / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / "novelty" / rel).write_text(text)
    found = private_imports(import_levels.modules(tmp_path / "novelty"))
    assert found == ["novelty.b.z:1 novelty.a._y", "novelty.b.z:2 novelty.a.x._f", "novelty.b.z:4 novelty.a._y"]


def test_no_private_name_is_imported_across_packages():
    found = private_imports(import_levels.modules(PACKAGE))
    assert not found, f"private names imported from another package (give them a public name or a door): {found}"


# ------------------------------------------------------------- a parameter's walk, as the engine guide lists it
#: the most stops a parameter takes from novelty.make to its multiply
MAX_STOPS = 12


def _walk() -> list[tuple[str, list[str], list[str]]]:
    """The stops of "The path of a parameter" in docs/guide/engine.md: (number, the functions
    named in its "where", the files they are in)."""
    text = (ROOT / "docs/guide/engine.md").read_text(encoding="utf-8")
    section = text.split("## The path of a parameter", 1)[1].split("\n## ", 1)[0]
    stops = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not cells[0].isdigit():
            continue
        spans = re.findall(r"`([^`]+)`", cells[1])
        files, folder = [], ""
        for span in spans:
            if span.endswith(".py"):
                folder = span.rpartition("/")[0] if "/" in span else folder
                files.append(span if "/" in span else f"{folder}/{span}")
        names = [span for span in spans if not span.endswith(".py")]
        stops.append((cells[0], names, files))
    return stops


def test_a_parameters_walk_is_at_most_twelve_stops_each_where_the_guide_says():
    stops = _walk()
    assert [number for number, _, _ in stops] == [str(i) for i in range(1, len(stops) + 1)], stops
    assert 0 < len(stops) <= MAX_STOPS, f"a learning rate walks {len(stops)} stops (at most {MAX_STOPS})"
    for number, names, files in stops:
        assert names and files, f"stop {number} names no function or no file"
        sources = "\n".join((ROOT / f).read_text(encoding="utf-8") for f in files)
        for name in names:
            last = name.rpartition(".")[2]
            assert re.search(rf"^\s*(?:def|class) {re.escape(last)}\b", sources, re.MULTILINE), (
                f"stop {number}: {name} is not defined in {files}")
