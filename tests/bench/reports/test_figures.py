"""File names made from labels: safe, bounded, one file a label."""

import numpy as np

from novelty import bench
from novelty.bench.reports.figures import MAX_SLUG, slug


def test_two_labels_never_write_one_file_and_no_name_is_too_long():
    labels = ["lab a", "lab/a", "lab-a", "x" * 300, "x" * 299 + "y", "é"]
    names = [slug(label) for label in labels]
    assert len(set(names)) == len(labels) and all(len(n) <= MAX_SLUG for n in names)
    assert slug("lab-a") == "lab-a"                       # a safe label is its own name


def test_a_long_task_label_runs_and_plots(tmp_path):
    rng = np.random.default_rng(0)
    X_train, X_test = rng.random((40, 2)), rng.random((20, 2))
    X_test[:5] += 1.0
    label = "corridor " * 40                              # 360 characters: "File name too long" before
    results = bench.run(["parzen"], {label: (X_train, X_test, np.r_[np.ones(5), np.zeros(15)])}, out=tmp_path)
    assert results.rows[0]["status"] == "ok"
    assert any(p.name.startswith("route-corridor-corridor") for p in results.report.files)
