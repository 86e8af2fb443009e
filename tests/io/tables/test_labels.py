"""Novelty labels are 0 and 1: every other reading is refused, saying where and what to do."""

import numpy as np
import pytest

from novelty.io.tables.labels import check_both_classes, check_labels


def test_zero_one_labels_of_any_numeric_type_pass():
    assert check_labels(np.array([0.0, 1.0, 1.0])).tolist() == [0, 1, 1]
    assert check_labels(np.array([False, True])).dtype == np.int64


@pytest.mark.parametrize("labels, message", [
    ([0, np.nan, 1], r"row 1: the label is NaN"),
    ([1, -1, 1, 1], r"scikit-learn's outlier convention .* convert with y = \(y == -1\)\.astype\(int\)"),
    ([0, 0.5, 1], r"row 1: expected a label 0 \(normal\) or 1 \(novel\), got 0\.5"),
    ([0, 2, 1], r"got 2"),
    (["a", "b"], r"row 0: expected a label 0 \(normal\) or 1 \(novel\), got 'a'"),
])
def test_other_labels_are_refused_with_where_and_why(labels, message):
    with pytest.raises(ValueError, match=message):
        check_labels(labels)


def test_a_test_part_needs_both_classes():
    with pytest.raises(ValueError, match="no novel scan"):
        check_both_classes([0, 0], "t")
    with pytest.raises(ValueError, match="no normal scan"):
        check_both_classes([1, 1], "t")
    check_both_classes([0, 1], "t")
