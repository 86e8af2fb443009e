"""Seeds aggregated per task: means, intervals over seeds, seeds that repeat one measurement."""

import math

import numpy as np
import pytest
from scipy import stats as sps

from novelty.bench.stats.aggregate import distinct, seed_interval, task_table


def _rows(values):
    return [{"cell_id": f"{d}{t}{s}", "detector": d, "task": t, "seed": s, "status": "ok", "roc_auc": v}
            for (d, t), seeds in values.items() for s, v in enumerate(seeds)]


def test_the_interval_over_seeds_is_students_t():
    v = np.array([0.7, 0.8, 0.9, 0.75])
    half = sps.t.ppf(0.975, 3) * v.std(ddof=1) / 2
    assert seed_interval(v) == pytest.approx((v.mean() - half, v.mean() + half))


def test_seeds_that_repeat_one_value_are_one_measurement():
    rows = _rows({("a", "fixed"): [0.8, 0.8, 0.8], ("b", "fixed"): [0.6, 0.6, 0.6],
                  ("a", "random"): [0.8, 0.7, 0.9], ("b", "random"): [0.6, 0.6, 0.6]})
    table = task_table(rows)
    assert table.n_distinct.tolist() == [[1, 3], [1, 1]]
    assert table.repeated_tasks() == ["fixed"]   # on "random" detector a's seeds differ
    assert all(math.isnan(x) for x in table.ci[0, 0]) and not math.isnan(table.ci[0, 1, 0])
    assert distinct([0.5, 0.5 + 1e-14]) == 1 and distinct([]) == 0


def test_a_failed_or_undefined_cell_counts_for_no_seed():
    rows = _rows({("a", "t"): [0.8, None]})
    rows[1]["status"] = "error"
    table = task_table(rows)
    assert table.n_seeds.tolist() == [[1]] and table.values.tolist() == [[0.8]]
