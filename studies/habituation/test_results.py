"""The habituation study's committed results are whole and its report says what they hold.

Each run's ``results.csv`` (``results/<run>/`` beside this file) holds every cell of its suite, each ok; the
report's tables (README.md, between ``<!-- scores: ... -->`` and ``<!-- end scores -->``) are what the scorer
prints from those rows; the candidate the report names as chosen is the first by the rule on the
development seeds; and the control's rows on the reported seeds are those of ``habituating-map`` committed for
``benchmarks/suites/maps-exploration.toml`` (the same preset, tasks and seeds).
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import pytest

from novelty.bench import load_suite

from . import scores as hs

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
RUNS = {"development": ("development-seen", "development-anywhere"), "reported": ("reported-seen", "reported-anywhere")}
REGION = re.compile(r"<!-- scores: (?P<key>[\w-]+) -->\n(?P<body>.*?)\n<!-- end scores -->", re.S)
#: what the exploration metrics compute, compared with the suite committed for the guides
COMPARED = ("first_encounter_auc", "excess_1", "excess_2", "excess_3", "first_separation", "false_alarm_rate")


def _rows(run: str) -> list[dict]:
    return hs.read_results(HERE / "results" / run)


@pytest.mark.parametrize("run", [run for runs in RUNS.values() for run in runs])
def test_each_run_holds_every_cell_of_its_suite_and_each_is_ok(run):
    suite = load_suite(HERE / f"habituation-{run}.toml")
    rows = _rows(run)
    expected = {(d.label or d.name, t.label or t.name, s) for d in suite.detectors for t in suite.tasks
                for s in suite.seeds}
    assert {(r["detector"], r["task"], int(r["seed"])) for r in rows} == expected
    assert len(rows) == len(expected)
    assert all(r["status"] == "ok" for r in rows)


def _regions() -> dict:
    return {m["key"]: m["body"] for m in REGION.finditer((HERE / "README.md").read_text(encoding="utf-8"))}


@pytest.mark.parametrize("key", sorted(RUNS))
def test_the_report_s_tables_are_the_scorer_s(key):
    rows = [row for run in RUNS[key] for row in _rows(run)]
    assert _regions()[key] == hs.table(hs.scores(rows))


def test_the_chosen_candidate_is_the_first_by_the_rule():
    rows = [row for run in RUNS["development"] for row in _rows(run)]
    first = hs.scores(rows)[0]["candidate"]
    chosen = re.search(r"The rule chooses `([\w.-]+)`", (HERE / "README.md").read_text(encoding="utf-8"))
    assert chosen and chosen.group(1) == first
    reported = {r["detector"] for run in RUNS["reported"] for r in _rows(run)}
    assert reported == {first, "defaults"}


def test_the_control_on_the_reported_seeds_is_the_committed_habituating_map():
    with open(ROOT / "benchmarks" / "results" / "maps-exploration" / "results.csv", newline="", encoding="utf-8") as fh:
        committed = {(r["task"], int(r["seed"])): r for r in csv.DictReader(fh) if r["detector"] == "habituating-map"}
    ours = [r for run in RUNS["reported"] for r in _rows(run) if r["detector"] == "defaults"]
    assert ours
    for row in ours:
        theirs = committed[(row["task"], int(row["seed"]))]
        for name in COMPARED:
            a, b = float(row[name] or "nan"), float(theirs[name] or "nan")
            assert (math.isnan(a) and math.isnan(b)) or a == b, (row["task"], row["seed"], name)
