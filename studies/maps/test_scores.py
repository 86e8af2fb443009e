"""The scorer of the habituating-map selections (studies/maps/scores.py): G with its threshold, F, H, S.

Rows are written by hand, so each score is checked against an answer known in advance: the guard's
threshold (0.5 until round 6, 0.55 in round 7) is strict, F takes the bar's 0.90 with the separation,
and the rule orders G before F + H before S.
"""

from __future__ import annotations

import pytest

from . import scores as mr

LOGS = ("intel", "aces", "csail")


def _row(detector, task, seed, auc, metric="roc_auc"):
    return {"detector": detector, "task": task, "seed": seed, "status": "ok", metric: auc}


def _explore(detector, task, seed, auc, e1=0.4, e3=0.4, separation=1.0):
    return {"detector": detector, "task": task, "seed": seed, "status": "ok", "policy": "online",
            "first_encounter_auc": auc, "excess_1": e1, "excess_2": (e1 + e3) / 2, "excess_3": e3,
            "novelty_range": 1.0, "first_separation": separation}


def _runs(detector, insp=0.8, first=0.7, guard=0.6, flag_intel=False, habituate_aces=False):
    inspection = [_row(detector, f"inspection-objects-radish-{log}", s, insp) for log in LOGS for s in (110, 111)]
    exploration = []
    for log in LOGS:
        task = f"exploration-objects-radish-{log}"
        auc = 0.95 if (flag_intel and log == "intel") else first
        e3 = 0.04 if (habituate_aces and log == "aces") else 0.4
        exploration += [_explore(detector, task, s, auc, e3=e3) for s in (110, 111)]
    guard_rows = [_row(detector, t, s, guard) for t in ("paper-a-to-b", "inspection-easy") for s in (115, 116)]
    return inspection, exploration, guard_rows


def _merge(*runs):
    return [sum((r[i] for r in runs), []) for i in range(3)]


def test_the_guard_threshold_is_strict_and_settable():
    runs = _runs("m", guard=0.55)
    assert mr.scores(*runs)[0]["G"]  # above 0.5
    assert not mr.scores(*runs, guard_above=0.55)[0]["G"]  # 0.55 is not above 0.55
    assert mr.scores(*_runs("m", guard=0.56), guard_above=0.55)[0]["G"]


def test_f_h_and_s_are_counted_from_the_rows():
    (rec,) = mr.scores(*_runs("m", insp=0.8, first=0.7, flag_intel=True, habituate_aces=True))
    assert (rec["F"], rec["H"]) == (1, 1)
    # S: the mean of three inspection AUCs (0.8) and three first sights (0.95, 0.7, 0.7)
    assert rec["S"] == pytest.approx((3 * 0.8 + 0.95 + 0.7 + 0.7) / 6)
    assert rec["first"] == pytest.approx([0.95, 0.7, 0.7])


def test_a_first_sight_of_0_85_does_not_count_toward_f():
    inspection, exploration, guard = _runs("m")
    exploration = [dict(r, first_encounter_auc=0.87) for r in exploration]
    assert mr.scores(inspection, exploration, guard)[0]["F"] == 0


def test_the_order_is_guard_then_f_plus_h_then_s():
    runs = _merge(_runs("a-fails-guard", guard=0.52, flag_intel=True, habituate_aces=True, insp=0.99),
                  _runs("b-passes", guard=0.6, insp=0.70),
                  _runs("c-passes-higher-s", guard=0.6, insp=0.75),
                  _runs("d-passes-with-h", guard=0.6, habituate_aces=True, insp=0.5))
    order = [r["candidate"] for r in mr.scores(*runs, guard_above=0.55)]
    assert order == ["d-passes-with-h", "c-passes-higher-s", "b-passes", "a-fails-guard"]
    # with the old threshold the first candidate passes and leads on F + H
    assert mr.scores(*runs)[0]["candidate"] == "a-fails-guard"


def test_a_folder_without_rows_is_an_error(tmp_path, capsys):
    with pytest.raises(SystemExit):
        mr.main(["--inspection", str(tmp_path), "--exploration", str(tmp_path), "--guard", str(tmp_path)])
    assert "no rows in" in capsys.readouterr().err
