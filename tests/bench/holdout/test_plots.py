"""The plots of a hold-out run: which seeds each shows, boxplots; with the critical-difference diagram."""

import pytest

pytest.importorskip("matplotlib", reason="plots need matplotlib (novelty-habituation[plot])")

import matplotlib  # noqa: E402

from novelty.bench import load_suite, quick_suite_path  # noqa: E402
from novelty.bench.holdout import plots  # noqa: E402
from novelty.bench.reports.critical_difference import plot_critical_difference  # noqa: E402
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


@pytest.mark.slow
def test_every_plot_of_the_quick_suite_says_which_seeds(quick, tmp_path, titles):
    paths = plots.plot_run(quick.rows, ResultsStore(quick.out).arrays, tmp_path)
    paths += plot_critical_difference(quick.rows, tmp_path)
    names = {p.name for p in paths}
    assert {"roc.png", "ranking.png", "boxplot-roc-auc.png", "critical-difference.png"} <= names
    assert all(p.stat().st_size > 1000 for p in paths)
    assert "one seed of each task" in " ".join(titles["roc.png"][0].split())
    assert "inspection-easy (seed 0)" in titles["roc.png"]
    assert titles["route-inspection-easy.png"][0].startswith("inspection-easy, seed 0: novelty")
    assert "seeds 0, 1" in titles["ranking.png"][0]
    assert titles["boxplot-roc-auc.png"][:2] == ["inspection-easy: ROC AUC over seeds 0, 1",
                                                 "paper-a-to-a-star: ROC AUC over seeds 0, 1"]
    caption = titles["critical-difference.png"][0]
    # 13 detectors on 2 tasks: Friedman's exact test can reach the level (its floor is 1/13!)
    assert caption.startswith("Average rank of ROC AUC over 2 tasks (1 = best; each task the mean over seeds 0, "
                              "1), in brackets; Friedman p = ")
    # the bars' test, and no other: Nemenyi's critical difference draws none of them
    assert "bars join detectors no test separates (exact Wilcoxon signed-rank over tasks, Holm, alpha = 0.05)" \
        in caption and "Nemenyi" not in caption
