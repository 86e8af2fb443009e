"""The exposures behind a 3rd/1st excess (studies/habituation/exposures.py), on arrays written by hand."""

from __future__ import annotations

import json

import numpy as np
import pytest

from . import exposures as ex


def _cell():
    """Two objects: 'a' met three times (1, 2 and 1 scans), 'b' twice (not recurring)."""
    feature = np.array(["", "a", "a", "a", "", "b", "b", "a", ""])
    exposure = np.array([-1, 0, 1, 1, -1, 0, 1, 2, -1])
    return {"feature": feature, "exposure": exposure, "curve_features": np.array(["a", "b"]),
            "curve_novelty": np.array([[0.9, 0.6, 0.5], [0.8, 0.4, np.nan]]),
            "curve_familiar": np.array([[0.5, 0.4, 0.2], [0.5, 0.5, np.nan]]),
            "curve_excess": np.array([[0.4, 0.2, 0.3], [0.3, -0.1, np.nan]])}


def test_a_recurring_object_s_exposures_are_read_and_counted():
    (rec,) = ex.exposures(_cell(), seed=7)
    assert rec["seed"] == 7 and rec["feature"] == "a"
    assert rec["scans"] == [1, 2, 1]
    assert rec["excess"] == pytest.approx([0.4, 0.2, 0.3])


def test_the_summary_says_how_much_of_the_3rd_excess_rests_on_few_scans():
    a = {"scans": [3, 3, 1], "novelty": [0.9, 0.6, 0.5], "familiar": [0.5, 0.4, 0.2], "excess": [0.4, 0.2, 0.3]}
    b = {"scans": [3, 3, 5], "novelty": [0.8, 0.6, 0.6], "familiar": [0.6, 0.5, 0.5], "excess": [0.2, 0.1, 0.1]}
    s = ex.summary([a, b])
    assert s["objects"] == 2 and s["thin_third"] == 1
    assert s["thin_share"] == pytest.approx(0.3 / 0.4)
    assert s["mean_novelty"] == pytest.approx([0.85, 0.6, 0.55])
    assert s["familiar_range"] == (0.2, 0.6)


def test_a_run_folder_is_read_cell_by_cell(tmp_path):
    (tmp_path / "cells").mkdir()
    np.savez(tmp_path / "cells" / "c1.npz", **_cell())
    rows = [{"cell_id": "c1", "detector": "d", "task": "t", "seed": 3},
            {"cell_id": "c2", "detector": "other", "task": "t", "seed": 3}]
    (tmp_path / "results.jsonl").write_text("\n".join(json.dumps(r) for r in rows) + "\n", encoding="utf-8")
    (rec,) = ex.read_cells(tmp_path, "d", "t")
    assert rec["seed"] == 3 and rec["scans"] == [1, 2, 1]
    assert ex.read_cells(tmp_path, "d", "another task") == []
