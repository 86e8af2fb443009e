"""Ranks, Friedman, Wilcoxon-Holm, Nemenyi and cliques over tasks against hand-computed and published values."""

import math

import numpy as np
import pytest
from scipy import stats as sps

from novelty.bench.stats import across_tasks as stats
from novelty.bench.stats.aggregate import TaskTable, task_table

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
    """A task table of one value a task (one seed each)."""
    values = np.asarray(values, dtype=float)
    names = names or [f"d{i}" for i in range(values.shape[0])]
    tasks = tasks or [f"t{t}" for t in range(values.shape[1])]
    ones = (~np.isnan(values)).astype(int)
    return TaskTable(list(names), list(tasks), values, ones, ones, np.full(values.shape + (2,), np.nan))


def test_ranks_within_a_cell_are_averaged_over_ties():
    ranks = stats.ranks_within(np.array([[0.9, 0.5], [0.7, 0.5], [0.9, 0.2]]))
    np.testing.assert_array_equal(ranks, [[1.5, 1.5], [3.0, 1.5], [1.5, 3.0]])


def test_task_ranks_rank_each_task_among_the_detectors_with_a_value():
    table = table_of([[0.8, 0.6], [0.8, 0.5], [0.6, np.nan]])
    np.testing.assert_array_equal(stats.task_ranks(table), [[1.5, 1.0], [1.5, 2.0], [3.0, np.nan]])


def test_friedman_by_hand():
    # ranks per cell (a, b, c): (1,2,3), (1,2,3), (1,3,2), (2,1,3); rank sums 5, 8, 11
    # chi2 = 12 / (N k (k+1)) * sum R^2 - 3 N (k+1) = 12/48 * 210 - 48 = 4.5; p = exp(-4.5/2) (2 df)
    table = table_of([[0.9, 0.8, 0.9, 0.6], [0.7, 0.6, 0.5, 0.7], [0.5, 0.4, 0.6, 0.3]])
    result = stats.friedman(table)
    assert (result.n_tasks, result.k) == (4, 3)
    assert result.statistic == pytest.approx(4.5)
    # Iman-Davenport: F = 3 * 4.5 / (4 * 2 - 4.5) = 27/7 on (2, 6) degrees of freedom
    assert result.f == pytest.approx(27 / 7)
    np.testing.assert_allclose(result.mean_ranks, [5 / 4, 8 / 4, 11 / 4])
    # exact p: of the 6^4 equally likely rankings, those with sum of squared rank sums >= 210;
    # counted by brute force here, against the randomization estimate (20,000 draws: se about 0.003)
    import itertools
    perms = list(itertools.permutations([1, 2, 3]))
    hits = sum(sum(sum(p[i] for p in combo) ** 2 for i in range(3)) >= 210
               for combo in itertools.product(perms, repeat=4))
    assert result.pvalue == pytest.approx(hits / 6 ** 4, abs=0.01)
    assert result.min_pvalue == pytest.approx(6.0 ** -3)


def test_friedman_with_two_tasks_ranked_alike_cannot_be_significant_with_three_detectors():
    # the chi-square approximation said p = 0.018 and Iman-Davenport F = inf; the exact p is 1/6
    result = stats.friedman(table_of([[0.9, 0.8], [0.7, 0.6], [0.5, 0.4]]))
    assert math.isinf(result.f)
    assert result.pvalue == pytest.approx(1 / 6, abs=0.01) and result.min_pvalue == pytest.approx(1 / 6)


def test_minimum_attainable_p_values():
    assert stats.wilcoxon_min_p(2) == 0.5 and stats.wilcoxon_min_p(8) == 2 / 256
    assert stats.friedman_min_p(3, 2) == pytest.approx(1 / 6)
    assert stats.friedman_min_p(4, 3) == pytest.approx(1 / 576)


def test_friedman_on_demsars_example_uses_only_complete_cells():
    # Demsar's uncorrected chi2 from the ranks of his table; scipy's divides by the tie correction
    # 1 - sum(t^3 - t) / (N k (k^2 - 1)): ties 4 (mushroom), 2+2+2+2 -> (60 + 4*6) / (14*4*15)
    values = np.c_[DEMSAR, [0.5, np.nan, 0.5, 0.5]]   # a 15th cell one detector did not complete
    result = stats.friedman(table_of(values))
    assert result.n_tasks == 14
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


@pytest.mark.parametrize("seed", range(3))
def test_the_exact_wilcoxon_equals_scipys_exact_test_without_ties(seed):
    rng = np.random.default_rng(seed)
    a, b = rng.random(9), rng.random(9)
    assert stats.wilcoxon(a, b)[2] == pytest.approx(sps.wilcoxon(a - b, method="exact").pvalue)


def test_the_exact_wilcoxon_with_two_tasks_cannot_go_below_one_half():
    assert stats.wilcoxon(np.array([0.9, 0.8]), np.array([0.1, 0.2]))[2] == 0.5


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

def test_the_task_table_averages_the_seeds_first(rows):
    table = task_table(rows)
    assert table.detectors == ["ref", "a", "b"] and table.tasks == ["t1", "t2"]
    np.testing.assert_allclose(table.row("b"), [0.80, 0.825])
    np.testing.assert_allclose(table.row("a"), [0.80, 0.50])   # t2: its one completed seed
    assert table.n_seeds.tolist() == [[2, 2], [2, 1], [2, 2]]
    assert table.complete().tasks == ["t1", "t2"]


def test_paired_differences_over_tasks_by_hand(rows):
    records = {r["detector"]: r for r in stats.paired_comparison(task_table(rows), "ref")}
    # b - ref per task: 0.80 - 0.75 = +0.05, 0.825 - 0.75 = +0.075 -> mean 0.0625, se 0.0125
    b = records["b"]
    assert b["n"] == 2 and (b["wins"], b["ties"], b["losses"]) == (2, 0, 0)
    assert b["mean_diff"] == pytest.approx(0.0625)
    assert b["se"] == pytest.approx(0.0125)
    # a - ref: +0.05, -0.25
    a = records["a"]
    assert (a["wins"], a["losses"]) == (1, 1) and a["mean_diff"] == pytest.approx(-0.1)
    assert records["ref"]["n"] == 2


def test_a_single_shared_task_has_no_standard_error():
    rows = rows_of({"ref": {("t", 0): 0.5}, "a": {("t", 0): 0.75}})
    (_, a) = stats.paired_comparison(task_table(rows), "ref")
    assert a["mean_diff"] == 0.25 and math.isnan(a["se"]) and a["wins"] == 1


def test_an_unknown_reference_names_the_detectors(rows):
    with pytest.raises(ValueError, match="'parzen' is not in this run; expected one of ref, a, b"):
        stats.paired_comparison(task_table(rows), "parzen")
