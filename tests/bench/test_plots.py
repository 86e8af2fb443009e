"""The plots of a run: which seeds each shows, boxplots, the critical-difference diagram."""

import numpy as np
import pytest

pytest.importorskip("matplotlib", reason="plots need matplotlib (novelty-habituation[plot])")

import matplotlib  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

from novelty.bench import load_suite, quick_suite_path  # noqa: E402
from novelty.bench import plots  # noqa: E402
from novelty.bench.results import ResultsStore  # noqa: E402
from novelty.bench.runner import run_bench  # noqa: E402

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """The embedded quick suite, run once for this module (no memory tracing, no plots)."""
    suite = load_suite(quick_suite_path())
    suite.memory = False
    out = tmp_path_factory.mktemp("quick")
    report = run_bench(suite, out, quiet=True, plots=False)
    assert report.failed == 0
    return report


@pytest.fixture
def titles(monkeypatch):
    """The titles of every figure saved, by file name."""
    seen = {}
    save = matplotlib.figure.Figure.savefig

    def record(fig, path, *args, **kwargs):
        texts = [fig._suptitle.get_text()] if fig._suptitle else []
        seen[path.name] = texts + [ax.get_title() for ax in fig.axes]
        return save(fig, path, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", record)
    return seen


def test_every_plot_of_the_quick_suite_says_which_seeds(quick, tmp_path, titles):
    paths = plots.plot_run(quick.rows, ResultsStore(quick.out).arrays, tmp_path)
    names = {p.name for p in paths}
    assert {"roc.png", "ranking.png", "boxplot-roc-auc.png", "critical-difference.png"} <= names
    assert all(p.stat().st_size > 1000 for p in paths)
    assert "lowest seed" in titles["roc.png"][0] and "inspection-easy (seed 0)" in titles["roc.png"]
    assert titles["route-inspection-easy.png"][0].startswith("inspection-easy, seed 0 (the lowest)")
    assert "seeds 0, 1" in titles["ranking.png"][0]
    assert titles["boxplot-roc-auc.png"][:2] == ["inspection-easy: ROC AUC over seeds 0, 1",
                                                 "paper-a-to-a-star: ROC AUC over seeds 0, 1"]
    caption = titles["critical-difference.png"][0]
    assert caption.startswith("Average rank of ROC AUC over 4 cells (tasks x seeds 0, 1); Friedman p = ")
    assert "Wilcoxon signed-rank, Holm, alpha = 0.05" in caption


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
