"""The scorer of the habituation study (studies/habituation/scores.py): H with the separation guard, the two
guards against the control, the rule's order and the bar.

Rows are written by hand, so each score is checked against an answer known in advance.
"""

from __future__ import annotations

import csv

import pytest

from . import scores as hs


def _row(detector, task, seed, auc=0.8, e1=0.4, e3=0.4, separation=1.0, false_alarms=0.02):
    return {"detector": detector, "task": task, "seed": seed, "status": "ok", "policy": "online",
            "first_encounter_auc": auc, "excess_1": e1, "excess_2": (e1 + e3) / 2, "excess_3": e3,
            "novelty_range": 1.0, "first_separation": separation, "false_alarm_rate": false_alarms}


def _candidate(name, habituate=(), **kw):
    """Rows of two seeds on the six tasks; on the seen-place tasks named in ``habituate`` the 3rd excess is a
    tenth of the 1st."""
    rows = []
    for task in hs.TASKS + hs.SEEN:
        e3 = 0.04 if task in habituate else 0.4
        rows += [_row(name, task, seed, e3=e3, **kw) for seed in (100, 101)]
    return rows


def test_h_counts_the_seen_places_on_which_it_habituates():
    rows = _candidate("defaults") + _candidate("m", habituate=hs.SEEN[:2] + hs.TASKS[:1])
    rec = {r["candidate"]: r for r in hs.scores(rows)}
    assert rec["m"]["H"] == 2  # a plain task habituating does not count
    assert rec["m"]["ratio"][hs.SEEN[0]] == pytest.approx(0.1)
    assert rec["defaults"]["H"] == 0 and not rec["m"]["bar"]


def test_a_ratio_within_the_quarter_does_not_count_without_the_separation():
    rows = _candidate("defaults") + _candidate("m", habituate=hs.SEEN, separation=0.4)
    rec = {r["candidate"]: r for r in hs.scores(rows)}
    assert rec["m"]["H"] == 0
    rows = _candidate("defaults") + _candidate("m", habituate=hs.SEEN, separation=0.5)
    rec = {r["candidate"]: r for r in hs.scores(rows)}
    assert rec["m"]["H"] == 3 and rec["m"]["bar"]


def test_the_guards_compare_with_the_control_within_their_margins():
    rows = (_candidate("defaults", auc=0.80, false_alarms=0.020)
            + _candidate("at-the-margins", auc=0.781, false_alarms=0.029)
            + _candidate("lower-first-sight", auc=0.779)
            + _candidate("more-false-alarms", false_alarms=0.031))
    rec = {r["candidate"]: r for r in hs.scores(rows)}
    assert rec["at-the-margins"]["guards"]
    assert not rec["lower-first-sight"]["first_stays"] and rec["lower-first-sight"]["not_flagged"]
    assert rec["more-false-alarms"]["first_stays"] and not rec["more-false-alarms"]["not_flagged"]


def test_the_rule_orders_guards_then_h_then_first_sight():
    rows = (_candidate("defaults", auc=0.80)
            + _candidate("habituates-but-blind", habituate=hs.SEEN, auc=0.60)
            + _candidate("one-seen-place", habituate=hs.SEEN[:1], auc=0.79)
            + _candidate("sharper", auc=0.85))
    order = [r["candidate"] for r in hs.scores(rows)]
    assert order == ["one-seen-place", "sharper", "defaults", "habituates-but-blind"]


def test_first_sight_at_the_bar_needs_every_seen_place():
    rows = _candidate("defaults", auc=0.95)
    (rec,) = hs.scores(rows)
    assert rec["first_at_bar"] and rec["first"] == pytest.approx(0.95)
    rows = [dict(r, first_encounter_auc=0.89) if r["task"] == hs.SEEN[1] else r for r in rows]
    assert not hs.scores(rows)[0]["first_at_bar"]


def test_a_missing_control_is_said():
    with pytest.raises(ValueError, match="the control 'defaults'"):
        hs.scores(_candidate("m"))


def test_the_table_has_a_line_per_candidate():
    rows = _candidate("defaults") + _candidate("m", habituate=hs.SEEN)
    text = hs.table(hs.scores(rows))
    assert "| `m` | yes (yes, yes) | 3 | 0.800 | 0.020 | yes |" in text
    assert "| `m` | 0.800 / 0.800 / 0.800 | 1.00 / 1.00 / 1.00 | 0.400 / 0.400 / 0.400 | 0.220 / 0.220 / 0.220 " \
           "| 0.040 / 0.040 / 0.040 | 0.10 / 0.10 / 0.10 | yes / yes / yes |" in text


def test_a_committed_csv_scores_as_the_run_s_rows(tmp_path):
    rows = _candidate("defaults") + _candidate("m", habituate=hs.SEEN[:1], auc=0.81)
    with open(tmp_path / "results.csv", "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    read = hs.read_results(tmp_path)
    assert all(isinstance(r["excess_1"], str) for r in read)  # text, as a csv holds it
    assert hs.table(hs.scores(read)) == hs.table(hs.scores(rows))
    assert hs.read_results(tmp_path / "absent") == []
