"""Exploration plots: means over seeds that leave a gap where no seed has a value, without a warning."""

import warnings

import numpy as np

from novelty.bench.exploration.plots import mean_over_seeds


def test_the_mean_over_seeds_skips_missing_values_and_leaves_a_gap_where_all_miss():
    curves = [np.array([1.0, np.nan, np.nan, 4.0]), np.array([3.0, 2.0, np.nan, np.inf])]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's nanmean warned "Mean of empty slice" at position 2
        mean = mean_over_seeds(curves)
    np.testing.assert_array_equal(mean, [2.0, 2.0, np.nan, 4.0])
