"""The critical-difference diagram: bars across the groups' ranks, none without three detectors."""

import numpy as np
import pytest

pytest.importorskip("matplotlib", reason="plots need matplotlib (novelty-habituation[plot])")

import matplotlib  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

from novelty.bench.reports import critical_difference as plots  # noqa: E402

matplotlib.use("Agg")


def test_the_diagram_draws_one_bar_a_group_across_its_ranks():
    fig, ax = plt.subplots()
    names = ["a", "b", "c", "d", "e"]
    ranks = np.array([1.2, 2.0, 2.9, 3.5, 4.4])
    plots.draw_critical_difference(ax, names, ranks, [[0, 1], [2, 3, 4]])
    bars = [seg for c in ax.collections if max(c.get_linewidths()) == 3 for seg in c.get_segments()]
    spans = sorted((round(s[0][0], 2), round(s[1][0], 2)) for s in bars)
    assert spans == [(1.15, 2.05), (2.85, 4.45)]
    labels = {t.get_text() for t in ax.texts}
    assert {"a (1.20)", "e (4.40)"} <= labels
    plt.close(fig)


def test_no_diagram_without_three_detectors(tmp_path):
    rows = [{"cell_id": f"{d}{s}", "detector": d, "task": "t", "seed": s, "status": "ok", "roc_auc": v}
            for d, v in [("a", 0.6), ("b", 0.7)] for s in (0, 1)]
    assert plots.plot_critical_difference(rows, tmp_path) == []
