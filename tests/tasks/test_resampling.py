"""Resampling protocols: per-seed splits, bootstrap and subsample, clean or contaminated training, scaling."""

import numpy as np
import pytest

from novelty.data import Dataset
from novelty.tasks.resampling import ADBENCH, Resampling, resampled


@pytest.fixture
def table():
    rng = np.random.default_rng(0)
    X = np.c_[rng.normal(size=100), rng.normal(size=100) * 10 + 5]
    y = np.r_[np.zeros(90), np.ones(10)]              # stored with its anomalies last, as many files are
    return X, y


def test_a_stratified_split_keeps_each_class_in_proportion_and_changes_with_the_seed(table):
    X, y = table
    task = resampled(X, y, resample="stratified", test=0.3)
    a, b = task.for_seed(0), task.for_seed(1)
    assert (a.split == "test").sum() == 30 and a.test().y.sum() == 3 and a.train().y.sum() == 7
    assert not np.array_equal(a.X, b.X)                       # a split drawn for each seed
    np.testing.assert_array_equal(a.X, task.for_seed(0).X)     # and the same for the same seed
    assert sorted(map(tuple, a.X)) == sorted(map(tuple, X))    # every row once, nothing else


def test_bootstrap_and_subsample_resize_before_the_split(table):
    X, y = table
    up = Resampling("stratified", 0.3, min_rows=400).apply(Dataset("t", X, y=y), 0)
    down = Resampling("shuffled", 0.5, max_rows=40).apply(Dataset("t", X, y=y), 0)
    assert len(up) == 400 and set(map(tuple, up.X)) <= set(map(tuple, X))
    assert len(down) == 40 and len(set(map(tuple, down.X))) == 40     # drawn without replacement


def test_clean_training_drops_the_novel_scans_and_the_scaler_is_fitted_on_training(table):
    X, y = table
    task = resampled(X, y, resample="stratified", training="clean", scale="minmax").for_seed(0)
    train = task.train()
    assert train.y.sum() == 0 and len(train) == 63
    np.testing.assert_allclose(train.X.min(axis=0), 0.0, atol=1e-12)
    np.testing.assert_allclose(train.X.max(axis=0), 1.0, atol=1e-12)
    standard = resampled(X, y, resample="shuffled", scale="standard").for_seed(0).train().X
    np.testing.assert_allclose(standard.mean(axis=0), 0.0, atol=1e-12)


def test_the_protocol_says_what_it_does():
    text = Resampling(**ADBENCH).describe()
    assert text == ("a stratified 70/30 train/test split drawn for each seed; bootstrapped to 1,000 rows when fewer "
                    "and subsampled to 10,000 rows when more (before the split); novel scans kept in training, "
                    "unlabelled (contaminated: outlier detection); min-max scaled by the training part")


@pytest.mark.parametrize("options, message", [
    (dict(resample="random"), "resample must be one of stratified, shuffled"),
    (dict(test=0.3), "give resample=stratified"),
    (dict(resample="shuffled", test=1.5), r"in \(0, 1\)"),
    (dict(resample="shuffled", min_rows=50, max_rows=10), "must not exceed"),
    (dict(resample="shuffled", scale="robust"), "scale must be one of none, minmax, standard"),
    (dict(resample="shuffled", training="dirty"), "training must be one of contaminated, clean"),
])
def test_bad_options_are_refused_by_name(table, options, message):
    with pytest.raises(ValueError, match=message):
        resampled(*table, **options)


def test_arrays_need_a_drawn_split_and_valid_labels(table):
    X, y = table
    with pytest.raises(ValueError, match="needs resample"):
        resampled(X, y)
    with pytest.raises(ValueError, match="scikit-learn's outlier convention"):
        resampled(X, np.where(y == 1, -1, 1), resample="stratified")
