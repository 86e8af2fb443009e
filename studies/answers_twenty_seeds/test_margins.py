"""studies/answers_twenty_seeds/margins.py: each mean's t interval and where it lies, on rows written by hand."""

from __future__ import annotations

import json
import math

import pytest

from . import margins as gm


def row(det, task, seed, auc, status="ok"):
    return {"detector": det, "task": task, "seed": seed, "roc_auc": auc, "status": status}


def test_the_interval_is_students_t_by_hand():
    # 0.4, 0.6, 0.8: mean 0.6, sd 0.2; t(0.975, 2) = 4.302653 -> half-width 4.302653 * 0.2 / sqrt(3) = 0.496827
    mean, sd, low, high = gm.interval([0.4, 0.6, 0.8])
    assert mean == pytest.approx(0.6) and sd == pytest.approx(0.2)
    assert low == pytest.approx(0.6 - 0.496827, abs=1e-6) and high == pytest.approx(0.6 + 0.496827, abs=1e-6)
    assert all(math.isnan(v) for v in gm.interval([0.7])[1:])


def test_where_an_interval_lies():
    assert gm.where(0.501, 0.7) == "above chance"
    assert gm.where(0.5, 0.7) == "at chance"          # its lower end is chance itself
    assert gm.where(0.3, 0.499) == "below chance"
    assert gm.where(0.45, 0.55) == "at chance"


def test_margins_count_failed_cells_and_seeds_at_or_below_chance():
    rows = [row("a", "t", s, v) for s, v in enumerate([0.55, 0.5, 0.6, 0.45])] + [row("a", "t", 9, None, "failed")]
    (rec,) = gm.margins(rows)
    assert rec["n"] == 4 and rec["failed"] == 1 and rec["at_or_below"] == 2
    assert rec["mean"] == pytest.approx(0.525) and rec["where"] == "at chance"


def test_paired_difference_is_per_seed_over_the_tasks_both_did():
    rows = [row("a", "t1", 0, 0.8), row("a", "t2", 0, 0.6), row("b", "t1", 0, 0.7), row("b", "t2", 0, 0.7),
            row("a", "t1", 1, 0.9), row("a", "t2", 1, 0.5), row("b", "t1", 1, 0.6), row("b", "t2", 1, 0.6)]
    p = gm.paired(rows, "a", "b")
    # seed 0: (0.1 - 0.1) / 2 = 0; seed 1: (0.3 - 0.1) / 2 = 0.1
    assert p["difference"] == pytest.approx(0.05) and p["seeds"] == 2 and p["tasks"] == 2
    assert p["mean_a"] == pytest.approx(0.7) and p["mean_b"] == pytest.approx(0.65)
    with pytest.raises(ValueError, match="share no task"):
        gm.paired(rows, "a", "c")


def test_a_folder_without_rows_is_an_error_naming_it(tmp_path, capsys):
    with pytest.raises(SystemExit, match="no rows"):
        gm.main([str(tmp_path)])
    rows = [dict(row("a", "t", s, 0.7 + 0.01 * s), cell_id=f"c{s}") for s in range(3)]
    (tmp_path / "results.jsonl").write_text("\n".join(json.dumps(r) for r in rows))
    gm.main([str(tmp_path)])
    out = capsys.readouterr().out
    assert "| `a` | `t` | 3 | 0.710 |" in out and "above chance" in out
