"""The scorer of studies/learning_answer/learning-answer.md (studies/learning_answer/scores.py): its order and its decision.

Records and rows are written by hand, so that each step of the rule is checked against an answer known
in advance: the guard on both seed sets, B before V before S, and the incumbent kept unless beaten on
S by the margin.
"""

from __future__ import annotations

import math

import pytest

from . import scores as la


def record(name, G=True, B=0, V=0, S=0.7):
    return {"candidate": name, "G": G, "B": B, "V": V, "S": S}


def test_guard_comes_first_then_b_then_v_then_s():
    recs = [record("a", G=False, B=5, V=10, S=0.99), record("b", B=0, V=3, S=0.6),
            record("c", B=1, V=1, S=0.5), record("d", B=0, V=3, S=0.65)]
    assert [r["candidate"] for r in la.ordered(recs)] == ["c", "d", "b", "a"]


def test_the_incumbent_is_kept_unless_beaten_by_the_margin_on_s():
    explore = record("explore", V=2, S=0.700)
    assert la.answer([explore, record("map", V=2, S=0.705)]) == "explore"  # ahead by 0.005 < 0.01
    assert la.answer([explore, record("map", V=2, S=0.711)]) == "map"
    assert la.answer([explore, record("map", V=3, S=0.500)]) == "map"  # ahead on V: S does not matter
    assert la.answer([explore, record("map", G=False, B=4, V=8, S=0.9)]) == "explore"  # fails the guard
    assert la.answer([record("explore", G=False), record("map", S=0.1)]) == "map"


def test_an_equal_record_does_not_displace_the_incumbent():
    assert la.answer([record("map", V=2, S=0.7), record("explore", V=2, S=0.7)]) == "explore"
    assert la.ordered([record("a-map", S=0.7), record("explore", S=0.7)])[0]["candidate"] == "explore"


def _guard_row(detector, task, seed, auc, status="ok"):
    return {"detector": detector, "task": task, "seed": seed, "roc_auc": auc, "status": status}


def _exploration_row(detector, task, seed, auc, e1=0.4, e3=0.04, separation=1.0):
    return {"detector": detector, "task": task, "seed": seed, "status": "ok", "policy": "online",
            "first_encounter_auc": auc, "excess_1": e1, "excess_2": (e1 + e3) / 2, "excess_3": e3,
            "novelty_range": 1.0, "first_separation": separation}


def test_the_guard_needs_both_seed_sets_above_chance():
    rows = [_guard_row("m", "t", 5, 0.6), _guard_row("m", "t", 6, 0.6), _guard_row("m", "t", 105, 0.6)]
    means = la.guard_means(rows)
    assert means == {("m", "5-9", "t"): pytest.approx(0.6), ("m", "105-109", "t"): pytest.approx(0.6)}
    explo = [_exploration_row("m", "x", 100, 0.9)]
    assert la.scores(explo, rows)[0]["G"]
    # the reported seeds alone missing: no pass
    assert not la.scores(explo, [r for r in rows if r["seed"] >= 100])[0]["G"]
    # a mean of exactly 0.5 is chance, not above it; a failed cell makes the mean NaN, which fails
    assert not la.scores(explo, rows + [_guard_row("m", "t", 7, 0.3)])[0]["G"]  # (0.6+0.6+0.3)/3 = 0.5
    assert not la.scores(explo, rows + [_guard_row("m", "t", 7, None, status="failed")])[0]["G"]


def test_scores_count_the_tables_verdicts():
    # task x: flags (0.9 >= 0.85) and habituates (3rd/1st 0.1); task y: neither (0.6; 3rd/1st 1.0)
    rows = [_exploration_row("m", "x", s, 0.9) for s in (100, 101)]
    rows += [_exploration_row("m", "y", s, 0.6, e1=0.4, e3=0.4) for s in (100, 101)]
    (rec,) = la.scores(rows, [])
    assert (rec["B"], rec["V"]) == (1, 2)
    assert rec["S"] == pytest.approx(0.75)
    assert rec["flags"] == [True, False] and rec["habituates"] == [True, False]
    assert not rec["G"]  # no guard rows at all


def test_a_task_without_a_verdict_counts_as_none():
    rows = [_exploration_row("a", "x", 100, 0.9), _exploration_row("a", "y", 100, 0.9),
            _exploration_row("b", "x", 100, 0.9)]
    by = {r["candidate"]: r for r in la.scores(rows, [])}
    assert by["a"]["V"] == 4 and by["b"]["V"] == 2
    assert math.isnan(by["b"]["S"])


def test_without_an_incumbent_the_answer_must_pass_the_guard():
    # learning-answer-no-pose.md: the first in order if it passes G, else none
    assert la.answer_that_passes([record("a", G=False, B=3), record("b", B=0, S=0.6), record("c", B=1)]) == "c"
    assert la.answer_that_passes([record("a", G=False, B=3, S=0.9), record("b", G=False)]) is None
    assert la.answer_that_passes([]) is None
    # the incumbent's rule, given the same records, names a candidate that fails the guard
    assert la.answer([record("explore", G=False), record("a", G=False, B=3)]) == "a"


def test_a_folder_without_rows_is_an_error_not_an_answer(tmp_path, capsys):
    with pytest.raises(SystemExit):
        la.main(["--exploration", str(tmp_path / "missing"), "--guard", str(tmp_path), "--must-pass"])
    assert "no rows in" in capsys.readouterr().err
