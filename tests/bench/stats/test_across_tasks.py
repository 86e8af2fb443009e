"""Ranks, Friedman, Wilcoxon-Holm, Nemenyi and cliques against hand-computed and published values."""

import math

import numpy as np
import pytest
from scipy import stats as sps

from novelty.bench.stats import across_tasks as stats

from ..hand_rows import rows_of

#: Demsar (2006), table 2 and 6: AUC of C4.5, C4.5+m, C4.5+cf, C4.5+m+cf on 14 data sets
DEMSAR = np.array([
    [0.763, 0.768, 0.771, 0.798], [0.599, 0.591, 0.590, 0.569], [0.954, 0.971, 0.968, 0.967],
    [0.628, 0.661, 0.654, 0.657], [0.882, 0.888, 0.886, 0.898], [0.936, 0.931, 0.916, 0.931],
    [0.661, 0.668, 0.609, 0.685], [0.583, 0.583, 0.563, 0.625], [0.775, 0.838, 0.866, 0.875],
    [1.000, 1.000, 1.000, 1.000], [0.940, 0.962, 0.965, 0.962], [0.619, 0.666, 0.614, 0.669],
    [0.972, 0.981, 0.975, 0.975], [0.957, 0.978, 0.946, 0.970],
]).T


def table_of(values, names=None, tasks=None):
    values = np.asarray(values, dtype=float)
    names = names or [f"d{i}" for i in range(values.shape[0])]
    tasks = tasks or [("t", s) for s in range(values.shape[1])]
    return stats.CellTable(list(names), list(tasks), values)


def test_ranks_within_a_cell_are_averaged_over_ties():
    ranks = stats.ranks_within(np.array([[0.9, 0.5], [0.7, 0.5], [0.9, 0.2]]))
    np.testing.assert_array_equal(ranks, [[1.5, 1.5], [3.0, 1.5], [1.5, 3.0]])


def test_task_ranks_use_the_mean_over_seeds():
    cells = [("t1", 0), ("t1", 1), ("t2", 0), ("t2", 1)]
    table = table_of([[0.9, 0.7, 0.6, np.nan],    # t1 mean 0.8, t2 0.6 (one seed)
                      [0.8, 0.8, 0.5, 0.5],       # t1 mean 0.8, t2 0.5
                      [0.6, 0.6, np.nan, np.nan]], tasks=cells)  # t1 0.6, t2 none
    tasks, ranks = stats.task_ranks(table)
    assert tasks == ["t1", "t2"]
    np.testing.assert_array_equal(ranks, [[1.5, 1.0], [1.5, 2.0], [3.0, np.nan]])


def test_friedman_by_hand():
    # ranks per cell (a, b, c): (1,2,3), (1,2,3), (1,3,2), (2,1,3); rank sums 5, 8, 11
    # chi2 = 12 / (N k (k+1)) * sum R^2 - 3 N (k+1) = 12/48 * 210 - 48 = 4.5; p = exp(-4.5/2) (2 df)
    table = table_of([[0.9, 0.8, 0.9, 0.6], [0.7, 0.6, 0.5, 0.7], [0.5, 0.4, 0.6, 0.3]])
    result = stats.friedman(table)
    assert (result.n_cells, result.k) == (4, 3)
    assert result.statistic == pytest.approx(4.5)
    assert result.pvalue == pytest.approx(math.exp(-2.25))
    # Iman-Davenport: F = 3 * 4.5 / (4 * 2 - 4.5) = 27/7 on (2, 6) degrees of freedom
    assert result.f == pytest.approx(27 / 7)
    assert result.f_pvalue == pytest.approx(sps.f.sf(27 / 7, 2, 6))
    np.testing.assert_allclose(result.mean_ranks, [5 / 4, 8 / 4, 11 / 4])


def test_friedman_on_demsars_example_uses_only_complete_cells():
    # Demsar's uncorrected chi2 from the ranks of his table; scipy's divides by the tie correction
    # 1 - sum(t^3 - t) / (N k (k^2 - 1)): ties 4 (mushroom), 2+2+2+2 -> (60 + 4*6) / (14*4*15)
    values = np.c_[DEMSAR, [0.5, np.nan, 0.5, 0.5]]   # a 15th cell one detector did not complete
    result = stats.friedman(table_of(values))
    assert result.n_cells == 14
    ranks = stats.ranks_within(DEMSAR).mean(axis=1)
    uncorrected = 12 * 14 / (4 * 5) * (np.sum(ranks ** 2) - 4 * 25 / 4)
    assert result.statistic == pytest.approx(uncorrected / (1 - 84 / 840))
    assert result.statistic == pytest.approx(sps.friedmanchisquare(*DEMSAR).statistic)


def test_friedman_needs_three_detectors_and_says_nothing_when_all_tie():
    assert stats.friedman(table_of([[0.5, 0.6], [0.7, 0.8]])) is None
    assert stats.friedman(table_of([[0.5], [0.7], [0.6]])) is None
    tied = stats.friedman(table_of(np.ones((3, 4))))
    assert (tied.statistic, tied.pvalue) == (0.0, 1.0)


def test_wilcoxon_on_demsars_example():
    # C4.5+m against C4.5: R+ = 93, R- = 12 with the two zero differences split (Demsar 2006, 3.1.3)
    n, statistic, p = stats.wilcoxon(DEMSAR[1], DEMSAR[0])
    assert (n, statistic) == (14, 12.0)
    assert p < 0.05


def test_wilcoxon_without_a_difference_or_a_shared_cell():
    assert stats.wilcoxon(np.array([0.5, 0.7]), np.array([0.5, 0.7])) == (2, 0.0, 1.0)
    n, _, p = stats.wilcoxon(np.array([0.5, np.nan]), np.array([np.nan, 0.7]))
    assert n == 0 and math.isnan(p)


def test_holm_by_hand():
    # sorted 0.005, 0.01, 0.03, 0.04 -> x4, x3, x2, x1 = 0.02, 0.03, 0.06, 0.04 -> running max
    adjusted = stats.holm([0.01, 0.04, 0.03, 0.005, np.nan])
    np.testing.assert_allclose(adjusted, [0.03, 0.06, 0.06, 0.02, np.nan])
    assert stats.holm([0.6, 0.5]).tolist() == [1.0, 1.0]


def test_pairwise_tests_are_one_holm_family():
    table = table_of(DEMSAR[:3], names=["c45", "m", "cf"])
    pairs = stats.pairwise_wilcoxon(table)
    raw = [stats.wilcoxon(DEMSAR[i], DEMSAR[j])[2] for i, j in [(0, 1), (0, 2), (1, 2)]]
    expected = stats.holm(raw)
    assert pairs.adjusted[0, 1] == pairs.adjusted[1, 0] == pytest.approx(expected[0])
    assert pairs.adjusted[2, 1] == pytest.approx(expected[2])
    assert pairs.n[0, 2] == 14 and math.isnan(pairs.pvalue[1, 1])
    assert pairs.significant(alpha=1.0).sum() == 6


def test_nemenyi_cd_of_demsars_example():
    # k = 4, N = 14: q_0.05 = 2.569 (Demsar's table 5a), CD = 2.569 sqrt(4 * 5 / (6 * 14)) = 1.25
    assert stats.nemenyi_cd(4, 14) == pytest.approx(2.569 * math.sqrt(20 / 84), abs=1e-3)
    assert round(stats.nemenyi_cd(4, 14), 2) == 1.25


def test_cliques_of_a_constructed_example():
    # rank order a, b, c, d, e; significant pairs: a-c, a-d, a-e, b-d, b-e, c-e
    names = "abcde"
    significant = np.zeros((5, 5), dtype=bool)
    for x, y in ["ac", "ad", "ae", "bd", "be", "ce"]:
        i, j = names.index(x), names.index(y)
        significant[i, j] = significant[j, i] = True
    mean_ranks = [1.0, 2.0, 3.0, 4.0, 5.0]
    assert stats.cliques(mean_ranks, significant) == [[0, 1], [1, 2], [2, 3], [3, 4]]
    significant[2, 3] = significant[3, 2] = True   # now c and d differ too
    assert stats.cliques(mean_ranks, significant) == [[0, 1], [1, 2], [3, 4]]
    # order comes from the ranks, not from the indices; nothing significant: one group
    assert stats.cliques([3.0, 1.0, 2.0], np.zeros((3, 3), bool)) == [[1, 2, 0]]
    assert stats.cliques([1.0, 2.0], np.ones((2, 2), bool)) == []


# On the hand-made results table (tests.bench.hand_rows, the fixture rows)

def test_the_cell_table_holds_nan_for_a_failed_cell(rows):
    table = stats.cell_table(rows)
    assert table.detectors == ["ref", "a", "b"]
    assert table.cells == [("t1", 0), ("t1", 1), ("t2", 0), ("t2", 1)]
    assert table.row("b").tolist() == [0.85, 0.75, 0.70, 0.95]
    assert math.isnan(table.row("a")[3])
    assert table.complete().cells == [("t1", 0), ("t1", 1), ("t2", 0)]


def test_paired_differences_by_hand(rows):
    records = {r["detector"]: r for r in stats.paired_comparison(stats.cell_table(rows), "ref")}
    # a - ref on the three shared cells: +0.10, 0.00, -0.10 -> mean 0, sd 0.1, se 0.1 / sqrt(3)
    a = records["a"]
    assert a["n"] == 3 and (a["wins"], a["ties"], a["losses"]) == (1, 1, 1)
    assert a["mean_diff"] == pytest.approx(0.0, abs=1e-12)
    assert a["se"] == pytest.approx(0.1 / math.sqrt(3))
    # b - ref: +0.05, +0.05, +0.10, +0.05 -> mean 0.0625, sd 0.025, se 0.0125
    b = records["b"]
    assert b["n"] == 4 and (b["wins"], b["ties"], b["losses"]) == (4, 0, 0)
    assert b["mean_diff"] == pytest.approx(0.0625)
    assert b["se"] == pytest.approx(0.0125)
    ref = records["ref"]
    assert (ref["n"], ref["mean_diff"], ref["ties"]) == (4, 0.0, 4)


def test_a_single_shared_cell_has_no_standard_error():
    rows = rows_of({"ref": {("t", 0): 0.5}, "a": {("t", 0): 0.75}})
    (_, a) = stats.paired_comparison(stats.cell_table(rows), "ref")
    assert a["mean_diff"] == 0.25 and math.isnan(a["se"]) and a["wins"] == 1


def test_an_unknown_reference_names_the_detectors(rows):
    with pytest.raises(ValueError, match="'parzen' is not in this run; expected one of ref, a, b"):
        stats.paired_comparison(stats.cell_table(rows), "parzen")
