"""Results tables in README.md, docs/ and studies/, generated from the committed results of their suites.

A table in a document is a region between two markers::

    <!-- generated: exploration/exploration-open-door -->
    ...
    <!-- end generated -->

``exploration`` is a suite (``benchmarks/suites/exploration.toml``, whose
committed results are ``benchmarks/results/exploration/``) and the part after
the slash is the table: ``ranking`` (the ranked table of ``novelty bench``),
``places`` (objects tasks: ROC AUC on the objects in seen and in unseen places, per recording),
``per-task`` (ROC AUC per task, mean ± sd over seeds), ``overview`` (the
ranking's ROC AUC beside each task's mean), ``paired`` (each detector against
the suite's reference), or, for a suite of the exploration protocol,
``verdicts`` (each detector's mean first-encounter AUC over the tasks and
the tasks on which it flags, habituates, or both) or a task's name (its
table of first encounters and habituation). The region
holds a one-line caption (the command, the suite, its seeds, the versions and
revision that made the results) and the table, both formatted now from the
committed rows by the package's own report functions, so a change of the
formatting is regenerated, never edited by hand.

    python benchmarks/tables.py              # rewrite every generated region in place
    python benchmarks/tables.py --check      # exit 1 and print a diff where a region differs
    python benchmarks/tables.py --run exploration --jobs 2
                                             # run a suite, then commit its rows: results.csv
                                             # and provenance.json in benchmarks/results/<suite>/
    python benchmarks/tables.py --run exploration --from results/exploration
                                             # record a finished run of the suite instead

``results.csv`` is the file ``novelty bench`` writes, less the columns every
row repeats (versions, revision, host, platform: kept once in
``provenance.json``); the per-scan arrays and plots stay out of the
repository. ``provenance.json`` says how the rows were made: the command, the
package versions, the git revision, the date, how long the run took and on
how many cores.
"""

from __future__ import annotations

import argparse
import csv
import difflib
import importlib.util
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

from novelty.registry import RIVER_DETECTORS

ROOT = Path(__file__).resolve().parents[1]
SUITES = ROOT / "benchmarks" / "suites"
RESULTS = ROOT / "benchmarks" / "results"
RESULTS_CSV = "results.csv"
PROVENANCE = "provenance.json"
COMMAND = "python benchmarks/tables.py"
#: the regions of "Which detector?": made from several suites' rows by benchmarks/which_detector.py
WHICH_DETECTOR = "which-detector"
#: regions made by a study from its own committed results (``region(name)`` of its script), by key
STUDIES = {"alarms": ROOT / "studies" / "alarms" / "operating_point.py"}

REGION = re.compile(r"(<!-- generated: (?P<key>[\w.-]+/[\w.-]+) -->\n)(?P<body>.*?)(<!-- end generated -->)",
                    re.S)

#: columns that name a cell; read as text whatever they look like (a hex id can look like a number)
TEXT_COLUMNS = {"cell_id", "detector", "detector_name", "task", "task_name", "params", "task_options"}
#: columns of the bench that name the run, not the cell: kept once in provenance.json when all rows agree
RUN_COLUMNS = ("versions", "git_revision", "host", "platform")
#: the distributions whose versions a run records; the caption names those that compute results
VERSIONED = ("novelty-habituation", "numpy", "scipy", "scikit-learn", "numba", "river", "pyod", "joblib", "dask")
CAPTION_VERSIONS = ("python", "novelty-habituation", "numpy", "scipy", "scikit-learn", "numba", "river", "pyod")


# ------------------------------------------------------------------ reading results
def _shown(path: Path) -> Path:
    """``path`` relative to the repository where it is inside it."""
    return path.relative_to(ROOT) if path.is_relative_to(ROOT) else path


def _typed(values: list[str]):
    """A CSV column back to the values ``novelty bench`` wrote: int, float, bool, text; '' is None."""
    present = [v for v in values if v != ""]
    for kind in (int, float):
        try:
            converted = [kind(v) for v in present]
        except ValueError:
            continue
        it = iter(converted)
        return [None if v == "" else next(it) for v in values]
    if present and set(present) <= {"True", "False"}:
        return [None if v == "" else v == "True" for v in values]
    return [None if v == "" else v for v in values]


def read_csv_rows(path) -> list[dict]:
    """The rows of a ``results.csv``, each value of the type the bench wrote."""
    with open(path, newline="", encoding="utf-8") as fh:
        raw = list(csv.DictReader(fh))
    if not raw:
        return []
    columns = {}
    for name in raw[0]:
        values = [row[name] for row in raw]
        columns[name] = ([None if v == "" else v for v in values] if name in TEXT_COLUMNS else _typed(values))
    return [{name: columns[name][i] for name in columns} for i in range(len(raw))]


def committed_rows(suite: str) -> list[dict]:
    path = RESULTS / suite / RESULTS_CSV
    if not path.exists():
        raise FileNotFoundError(f"No committed results for suite {suite!r}: {_shown(path)} is missing; "
                                f"make them with '{COMMAND} --run {suite}'.")
    return read_csv_rows(path)


def provenance(suite: str) -> dict:
    return json.loads((RESULTS / suite / PROVENANCE).read_text(encoding="utf-8"))


# ------------------------------------------------------------------ the tables
def _table_lines(text: str) -> str:
    """The markdown table of a report section (its heading and notes left out)."""
    return "\n".join(line for line in text.splitlines() if line.startswith("|"))


def overview_text(rows: list[dict]) -> str:
    """Detectors in rank order: mean ROC AUC, then its mean on each task (the suite's order)."""
    from novelty.bench.reports.format import format_table
    from novelty.bench.reports.ranking import per_task, rank_detectors

    tasks = list(dict.fromkeys(r["task"] for r in rows))
    by_task = per_task(rows)
    body = [[str(r["rank"]), f"`{r['detector']}`", f"{r['roc_auc']:.3f}",
             *(f"{by_task[r['detector']][t][0]:.3f}" if t in by_task.get(r["detector"], {}) else "-" for t in tasks)]
            for r in rank_detectors(rows)]
    return format_table(["#", "detector", "ROC AUC", *tasks], body)


def verdicts_text(rows: list[dict]) -> str:
    """Exploration: each detector's mean first-encounter AUC over the tasks and where it flags and habituates."""
    from novelty.bench.exploration.summary import exploration_records
    from novelty.bench.reports.format import format_table

    records = exploration_records(rows)
    tasks = list(records)
    by_detector: dict[str, dict[str, dict]] = {}
    for task, found in records.items():
        for record in found:
            by_detector.setdefault(record["detector"], {})[task] = record

    def where(detector: str, verdict: str) -> str:
        names = [t.removeprefix("exploration-") for t in tasks if by_detector[detector].get(t, {}).get(verdict)]
        return str(len(names)) + (f" ({', '.join(names)})" if names else "")

    mean_auc = {d: sum(r["auc"] for r in found.values()) / len(found) for d, found in by_detector.items()}
    order = sorted(by_detector, key=lambda d: (-mean_auc[d], d))
    body = [[f"`{d}`", f"{mean_auc[d]:.3f}", where(d, "flags"), where(d, "habituates"), where(d, "both")]
            for d in order]
    return format_table(["detector", "mean first-encounter AUC", f"flags (of {len(tasks)} tasks)", "habituates",
                         "both"], body)


def _reference(suite: str) -> str | None:
    """The suite's reference detector (``reference`` in its [suite] table), as its summary pairs with."""
    from novelty.bench import load_suite

    return load_suite(SUITES / f"{suite}.toml").reference_label if (SUITES / f"{suite}.toml").exists() else None


def table(suite: str, name: str, rows: list[dict]) -> str:
    """The table ``name`` of ``suite`` from its rows, as markdown."""
    # the package's report formatting, public names only; imported here so that reading
    # this file's help or a region's key needs no numba compile
    from novelty.bench.exploration.summary import exploration_text
    from novelty.bench.holdout.summary import ranking_text
    from novelty.bench.reports.place_tables import places_text
    from novelty.bench.reports.ranking import per_task_text
    from novelty.bench.reports.statistics import paired_text

    if name == "ranking":
        return ranking_text(rows)
    if name == "per-task":
        return per_task_text(rows)
    if name == "paired":
        return _table_lines(paired_text(rows, _reference(suite)))
    if name == "overview":
        return overview_text(rows)
    if name == "places":
        return places_text(rows)
    tasks = sorted({r["task"] for r in rows})
    exploring = any(r.get("policy") for r in rows)
    if name == "verdicts" and exploring:
        return verdicts_text(rows)
    if name in tasks and exploring:
        return _table_lines(exploration_text([r for r in rows if r["task"] == name]))
    raise KeyError(f"Suite {suite!r} has no table {name!r}; tables: 'ranking', 'per-task', 'overview', 'paired', "
                   "'places'"
                   + (f", 'verdicts', or a task: {', '.join(tasks)}" if exploring else "") + ".")


def _seeds_text(seeds: list[int]) -> str:
    if seeds == list(range(seeds[0], seeds[-1] + 1)) and len(seeds) > 2:
        return f"seeds {seeds[0]}-{seeds[-1]}"
    return "seeds " + ", ".join(map(str, seeds))


def _short(revision: str) -> str:
    """A commit shortened to 12 characters, keeping "+dirty" (a run of modified code)."""
    commit, _, rest = revision.partition("+")
    return commit[:12] + ("+" + rest if rest else "")


def runnable(command: str) -> str:
    """A recorded command as a reader can run it: the folders of the machine that ran it (its leading
    ``NAME=value`` settings) become a word on where the variable should point.

    >>> runnable("NOVELTY_DATA_DIR=/data/uci novelty bench s.toml --out r")
    '`novelty bench s.toml --out r`, with `NOVELTY_DATA_DIR` naming your folder of the data sets'
    >>> runnable("novelty bench s.toml --out r")
    '`novelty bench s.toml --out r`'
    """
    words = command.split(" ")
    settings = []
    while words and re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", words[0]):
        settings.append(words.pop(0).split("=", 1)[0])
    named = " and ".join(f"`{name}`" for name in settings)
    return f"`{' '.join(words)}`" + (f", with {named} naming your folder of the data sets" if settings else "")


def caption(suite: str, rows: list[dict]) -> str:
    """One line: how to regenerate, from which results, seeds, versions and revision."""
    made = provenance(suite)
    seeds = sorted({r["seed"] for r in rows})
    versions = ", ".join(f"{k} {v}" for k, v in made["versions"].items() if k in CAPTION_VERSIONS)
    river = sorted({r["detector"] for r in rows if r.get("detector_name") in RIVER_DETECTORS})
    note = (f" {', '.join(f'`{d}`' for d in river)}: River's anomaly detectors, which `novelty bench` runs by "
            "name (extra `river`); not registered, as no model file holds a River model." if river else "")
    return (f"*Generated by `{COMMAND}` from `benchmarks/results/{suite}/`: {runnable(made['command'])}; "
            f"{_seeds_text(seeds)}; {versions}; revision {_short(made['revision'])}, {made['date'][:10]}.{note}*")


def region_body(key: str, cache: dict | None = None) -> str:
    """What the region ``<suite>/<table>`` holds: the caption, a blank line, the table; a region
    ``which-detector/<part>`` is made by ``benchmarks/which_detector.py`` from several suites' rows."""
    suite, name = key.split("/", 1)
    cache = {} if cache is None else cache

    def rows_of(suite: str) -> list[dict]:
        if suite not in cache:
            cache[suite] = committed_rows(suite)
        return cache[suite]

    if suite == WHICH_DETECTOR:
        return _which_detector().region(name, rows_of)
    if suite in STUDIES:
        return _script(suite, STUDIES[suite]).region(name)
    rows = rows_of(suite)
    return f"{caption(suite, rows)}\n\n{table(suite, name, rows)}\n"


def _which_detector():
    """``benchmarks/which_detector.py``, the answers of "Which detector?" (a script's neighbour, not a package)."""
    return _script("which_detector", Path(__file__).with_name("which_detector.py"))


def _script(name: str, path: Path):
    """The script at ``path`` as module ``name`` (a script, not a package: loaded by its path)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module  # its dataclasses look their module up
        spec.loader.exec_module(module)
    return sys.modules[name]


def regenerate(text: str, cache: dict | None = None) -> str:
    """``text`` with every generated region rewritten from the committed results."""
    cache = {} if cache is None else cache
    return REGION.sub(lambda m: m.group(1) + region_body(m.group("key"), cache) + m.group(4), text)


def documents() -> list[Path]:
    """README.md, the markdown pages of docs/ (not the built site or the API pages) and the studies' reports."""
    pages = [p for p in sorted((ROOT / "docs").rglob("*.md"))
             if not {"_build", "api"} & set(p.relative_to(ROOT / "docs").parts[:-1])]
    return [ROOT / "README.md", *pages, *sorted((ROOT / "studies").rglob("*.md"))]


def differences(paths=None) -> dict[Path, str]:
    """``{document: unified diff}`` for every document whose regions differ from their results."""
    cache: dict = {}
    out = {}
    for path in documents() if paths is None else paths:
        text = path.read_text(encoding="utf-8")
        new = regenerate(text, cache)
        if new != text:
            rel = _shown(path)
            out[path] = "".join(difflib.unified_diff(text.splitlines(True), new.splitlines(True),
                                                     f"{rel} (as written)", f"{rel} (from the results)"))
    return out


# ------------------------------------------------------------------ recording a run
def _git_revision() -> str:
    # the bench's own record of the code that runs (this checkout's commit, "+dirty" if modified)
    from novelty.bench.results import provenance as run_provenance

    return run_provenance()["git_revision"]


def _is_ancestor(older: str, newer: str) -> bool:
    """Whether commit ``older`` is an ancestor of ``newer`` in this checkout (False when git cannot tell)."""
    try:
        done = subprocess.run(["git", "-C", str(ROOT), "merge-base", "--is-ancestor", older, newer],
                              capture_output=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return False
    return done.returncode == 0


def _newest(revisions: set[str]) -> str | None:
    """Of clean revisions, the one that descends from all the others (a run resumed on later code); else None."""
    if not revisions or any("+" in r or r in ("unknown", "") for r in revisions):
        return None
    for candidate in sorted(revisions):
        if all(r == candidate or _is_ancestor(r, candidate) for r in revisions):
            return candidate
    return None


def _versions() -> dict:
    found = {"python": platform.python_version()}
    for dist in VERSIONED:
        try:
            found[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            continue
    return found


def record(suite: str, out: Path, command: str, elapsed_s: float | None, jobs: int | None,
           revision: str | None = None) -> Path:
    """Copy a run's ``results.csv`` into ``benchmarks/results/<suite>/`` with its provenance.

    The revision is ``revision``, else the one every row names ("unknown" for a run outside a
    checkout), else, when the rows name several (a run resumed on later code; each row keeps its
    own in ``results.csv``), the one that descends from the others, else this checkout's.
    """
    target = RESULTS / suite
    target.mkdir(parents=True, exist_ok=True)
    with open(Path(out) / RESULTS_CSV, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    # what every row repeats is said once, in provenance.json (a third of the file)
    same = {c: rows[0][c] for c in RUN_COLUMNS if rows and c in rows[0] and len({r[c] for r in rows}) == 1}
    with open(target / RESULTS_CSV, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, [c for c in (rows[0] if rows else []) if c not in same])
        writer.writeheader()
        writer.writerows({c: v for c, v in row.items() if c not in same} for row in rows)
    made = {
        "command": command,
        "suite": f"benchmarks/suites/{suite}.toml",
        "revision": revision or same.get("git_revision") or _newest({r.get("git_revision", "") for r in rows})
        or _git_revision(),
        "date": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "versions": _versions(),
        "elapsed_s": None if elapsed_s is None else round(elapsed_s),
        "jobs": jobs,
        "machine": f"{sys.platform}-{platform.machine()}, {os.cpu_count()} cores",
        "rows": {c: (json.loads(v) if c == "versions" else v) for c, v in same.items()},
    }
    (target / PROVENANCE).write_text(json.dumps(made, indent=2) + "\n", encoding="utf-8")
    return target


def run(suite: str, jobs: int) -> Path:
    """Run ``suite`` (plots and per-scan arrays in a temporary folder) and record its rows."""
    data = "NOVELTY_DATA_DIR=/data/uci " if os.environ.get("NOVELTY_DATA_DIR") else ""  # where, not which machine
    command = f"{data}novelty bench benchmarks/suites/{suite}.toml --out results/{suite} --jobs {jobs}"
    with tempfile.TemporaryDirectory(prefix=f"bench-{suite}-") as out:
        started = time.perf_counter()
        subprocess.run([sys.executable, "-m", "novelty.cli", "bench", str(SUITES / f"{suite}.toml"),
                        "--out", out, "--jobs", str(jobs), "--no-plots"], cwd=ROOT, check=True)
        return record(suite, Path(out), command, time.perf_counter() - started, jobs)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="compare only: exit 1 and print a diff")
    parser.add_argument("--run", metavar="SUITE", help="run benchmarks/suites/SUITE.toml and record its rows first")
    parser.add_argument("--jobs", type=int, default=2, help="cells run at once with --run (default 2)")
    parser.add_argument("--from", dest="source", metavar="DIR",
                        help="with --run: record the finished run in DIR (its --out) instead of running again")
    args = parser.parse_args(argv)
    if args.source and not args.run:
        parser.error("--from DIR needs --run SUITE: the suite the run in DIR is of")
    if args.run and args.source:
        command = f"novelty bench benchmarks/suites/{args.run}.toml (a finished run, recorded)"
        print(f"recorded {_shown(record(args.run, Path(args.source), command, None, None))}")
    elif args.run:
        print(f"recorded {_shown(run(args.run, args.jobs))}")
    diffs = differences()
    if args.check:
        for diff in diffs.values():
            sys.stdout.write(diff)
        return 1 if diffs else 0
    for path in diffs:
        path.write_text(regenerate(path.read_text(encoding="utf-8")), encoding="utf-8")
        print(f"rewrote {_shown(path)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
