"""A cell's warnings are counted and named in its row, the summary and the run's notes."""

import numpy as np

from novelty import bench


def test_warnings_raised_in_cells_are_counted_and_named():
    rng = np.random.default_rng(0)
    X_train, X_test = 10 * rng.random((60, 3)), 10 * rng.random((20, 3))   # far outside hsom's [0, 1]
    X_test[:4] += 20
    results = bench.run(["hsom"], {"unscaled": (X_train, X_test, np.r_[np.ones(4), np.zeros(16)])}, seeds=2)
    row = results.rows[0]
    assert row["n_warnings"] >= 1 and row["warning_types"] == "ScanRangeWarning"
    note = next(n for n in results.report.notes if n.startswith("Warnings"))
    assert note.startswith("Warnings were raised in 2 of 2 cells (ScanRangeWarning in 2)")
    assert "## Warnings raised in cells" in results.summary and "| ScanRangeWarning | 2" in results.summary
