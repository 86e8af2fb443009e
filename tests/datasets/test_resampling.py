"""Resampling protocols: per-seed splits, bootstrap and subsample, clean or contaminated training, scaling;
ADBench's draw against ADBench's own sequence of calls, and against its published table."""

import os
from pathlib import Path

import numpy as np
import pytest
from sklearn.model_selection import train_test_split

from novelty import bench
from novelty.data import Dataset
from novelty.datasets.resampling import ADBENCH, Resampling, adbench_split, resampled

REPO = Path(__file__).resolve().parents[2]


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
    text = Resampling("stratified", 0.3, 1000, 10000, "minmax", "contaminated").describe()
    assert text == ("a stratified 70/30 train/test split drawn for each seed; bootstrapped to 1,000 rows when fewer "
                    "and subsampled to 10,000 rows when more (before the split); novel scans kept in training, "
                    "unlabelled (contaminated: outlier detection); min-max scaled by the training part")
    assert Resampling(**ADBENCH).describe().startswith(
        "a stratified 70/30 train/test split drawn for each seed as ADBench's code draws it (numpy's "
        "RandomState(seed)); bootstrapped to 1,000 rows when fewer and subsampled to 10,000 rows when more")


@pytest.mark.parametrize("options, message", [
    (dict(resample="random"), "resample must be one of stratified, shuffled, adbench"),
    (dict(test=0.3), "give resample=stratified"),
    (dict(resample="shuffled", test=1.5), r"in \(0, 1\)"),
    (dict(resample="shuffled", min_rows=50, max_rows=10), "must not exceed"),
    (dict(resample="shuffled", min_rows=10**12), "min_rows must be a number of rows, 2 to 16,777,216; got 10000"),
    (dict(resample="shuffled", max_rows=2**24 + 1), "max_rows must be a number of rows, 2 to 16,777,216"),
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


def test_a_bootstrap_beyond_the_values_bound_is_refused_before_it_is_drawn():
    X, y = np.zeros((10, 16)), np.r_[np.zeros(8), np.ones(2)]
    task = resampled(X, y, resample="shuffled", min_rows=2**24)   # each option within its bound
    with pytest.raises(ValueError, match=r"min_rows=16,777,216 rows of 16 features make 268,435,456 values; "
                                         r"at most 134,217,728"):
        task.for_seed(0)


# ------------------------------------------------------------------ ADBench's draw
def _adbench_by_its_own_calls(y, seed, min_rows, max_rows):
    """The rows of ADBench's data generator, by its own sequence of calls on numpy's global state.

    ADBench's ``DataGenerator.generator`` with the default options of an unsupervised run: seed, bootstrap
    below ``min_rows`` or subsample above ``max_rows`` (seeding again first), then a stratified
    ``train_test_split`` without a ``random_state``. ``X`` holds each row's index, so that ``X_train`` and
    ``X_test`` say which rows were drawn, in their order.
    """
    X = np.arange(len(y))[:, None]
    np.random.seed(seed)
    if len(y) < min_rows:
        np.random.seed(seed)
        idx_duplicate = np.random.choice(np.arange(len(y)), min_rows, replace=True)
        X, y = X[idx_duplicate], y[idx_duplicate]
    if len(y) > max_rows:
        np.random.seed(seed)
        idx_sample = np.random.choice(np.arange(len(y)), max_rows, replace=False)
        X, y = X[idx_sample], y[idx_sample]
    X_train, X_test, y_train, y_test = train_test_split(X, y, test_size=0.3, shuffle=True, stratify=y)
    return X_train[:, 0], X_test[:, 0]


@pytest.fixture
def global_state():
    """numpy's global random state, put back as it was after the test (the reference above changes it)."""
    state = np.random.get_state()
    yield
    np.random.set_state(state)


@pytest.mark.parametrize("n", [30, 60, 90], ids=["bootstrapped", "as-is", "subsampled"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_adbench_draws_the_rows_of_adbenchs_own_calls(global_state, n, seed):
    y = np.zeros(n, dtype=np.int64)
    y[::7] = 1                                                   # anomalies spread through the table
    expected_train, expected_test = _adbench_by_its_own_calls(y, seed, min_rows=50, max_rows=80)
    np.random.seed(12345)                                        # our draw neither reads nor moves the global state
    before = np.random.get_state()[1].copy()
    train, test = adbench_split(y, seed, test=0.3, min_rows=50, max_rows=80)
    np.testing.assert_array_equal(train, expected_train)
    np.testing.assert_array_equal(test, expected_test)
    np.testing.assert_array_equal(np.random.get_state()[1], before)
    # the task built from it holds those rows, training rows first, in that order
    X = np.arange(float(n))[:, None]
    task = resampled(X, y, resample="adbench", min_rows=50, max_rows=80, scale="none").for_seed(seed)
    np.testing.assert_array_equal(task.train().X[:, 0], expected_train)
    np.testing.assert_array_equal(task.test().X[:, 0], expected_test)
    np.testing.assert_array_equal(task.y, y[np.r_[expected_train, expected_test]])


def test_adbench_fills_adbenchs_values_and_takes_the_options_given():
    assert Resampling("adbench").check() == Resampling(**ADBENCH).check()
    assert Resampling(**ADBENCH).check() == Resampling("adbench", 0.3, 1000, 10000, "minmax", "contaminated")
    mine = Resampling("adbench", training="clean", scale="none").check()
    assert (mine.min_rows, mine.max_rows, mine.test, mine.scale, mine.training) == (1000, 10000, 0.3, "none", "clean")


def test_adbench_trains_on_every_training_row_scaled_by_them(table):
    X, y = table
    task = resampled(X, y, resample="adbench").for_seed(1)
    assert len(task) == 1000 and (task.split == "train").sum() == 700       # bootstrapped to 1,000, 70/30
    anomalies = int(task.y.sum())
    assert abs(task.train().y.sum() - 0.7 * anomalies) <= 1                 # the anomalies stay, stratified
    np.testing.assert_allclose(task.train().X.min(axis=0), 0.0, atol=1e-12)
    np.testing.assert_allclose(task.train().X.max(axis=0), 1.0, atol=1e-12)


@pytest.mark.parametrize("seed", [-1, 2**32, 1.5, True])
def test_adbench_needs_a_seed_of_numpys_legacy_generator(seed):
    with pytest.raises(ValueError, match=r"the seed must be an integer in \[0, 2\*\*32\)"):
        adbench_split(np.r_[np.zeros(8), np.ones(4)], seed)


# ------------------------------------------------------------------ ADBench's published table
#: ADBench's Table D4 (AUCROC x 100, mean of seeds 1-3) for the shared files, from the README of their folder
TABLE_D4 = {"14_glass": {"lof": 69.20, "knn": 82.29, "one-class-svm[gamma=auto]": 35.36},
            "4_breastw": {"lof": 40.61, "knn": 97.01, "one-class-svm[gamma=auto]": 80.30},
            "6_cardio": {"lof": 66.33, "knn": 76.64, "one-class-svm[gamma=auto]": 93.91}}


def _adbench_files() -> Path:
    """ADBench's classical files shared beside the repository (or in ``$NOVELTY_DATA_DIR``), or skip."""
    candidates = [Path(os.environ["NOVELTY_DATA_DIR"])] if os.environ.get("NOVELTY_DATA_DIR") else []
    candidates += [REPO.parent / "shared" / "datasets", REPO.parent.parent / "shared" / "datasets"]
    folder = next((c / "adbench-classical" for c in candidates if (c / "adbench-classical").is_dir()), None)
    if folder is None:
        pytest.skip("ADBench's classical files (shared/datasets/adbench-classical beside the repository, or "
                    "$NOVELTY_DATA_DIR) are not on this machine")
    return folder


#: the one-line recipe that samples ADBench's protocol (each table its own draws), which the guide sets beside it
STRATIFIED = "resample=stratified test=0.3 min_rows=1000 max_rows=10000 scale=minmax training=contaminated"
GUIDE = REPO / "docs" / "guide" / "benchmarks.md"


def _measured(folder: Path, recipe: str) -> dict:
    """ROC AUC x 100, mean of seeds 1-3, rounded as the guide and Table D4 give it: {(file, detector): value}."""
    results = bench.run(["lof", "knn", "one-class-svm gamma=auto"], f"files path={folder} {recipe}", seeds=[1, 2, 3])
    scores: dict = {}
    for row in results.rows:
        assert row["status"] == "ok", row
        scores.setdefault((row["task"], row["detector"].replace("[gamma=auto]", " gamma=auto")), []).append(
            100 * row["roc_auc"])
    return {key: round(float(np.mean(v)), 2) for key, v in scores.items()}


def _guide_tables() -> dict:
    """The guide's tables of ADBench's recipe: {(file, detector): {column: value or None}}."""
    text = GUIDE.read_text(encoding="utf-8")
    tables = [block.split("\n\n")[0].splitlines()[3:] for block in text.split("<!-- checked: ADBench's Table D4")[1:]]
    files, cells = {}, {}
    for line in tables[0]:
        name, file, _, published, ours = (c.strip() for c in line.strip("|").split("|"))
        files[name] = file.strip("`").removesuffix(".npz")
        cells[files[name], "lof"] = {"Table D4": float(published), "adbench": float(ours) if ours else None}
    for line in tables[1]:
        name, detector, published, ours, stratified = (c.strip() for c in line.strip("|").split("|"))
        cell = cells.setdefault((files[name], detector.strip("`")), {})
        assert cell in ({}, {"Table D4": float(published), "adbench": float(ours)}), (name, detector)  # one value
        cell.update({"Table D4": float(published), "adbench": float(ours), "stratified": float(stratified)})
    return cells


@pytest.mark.slow
def test_the_adbench_recipe_reproduces_table_d4_and_the_guide_says_what_it_gives():
    folder = _adbench_files()
    adbench, stratified = _measured(folder, "resample=adbench"), _measured(folder, STRATIFIED)
    for task, published in TABLE_D4.items():
        for detector, value in published.items():
            detector = detector.replace("[gamma=auto]", " gamma=auto")
            assert adbench[task, detector] == pytest.approx(value, abs=0.2), (task, detector)
    guide = _guide_tables()
    for (task, detector), columns in guide.items():
        published = TABLE_D4.get(task, {}).get(detector.replace(" gamma=auto", "[gamma=auto]"))
        assert published is None or columns["Table D4"] == published, (task, detector)
        if published is not None:                                  # measured here: the three shared files
            assert columns["adbench"] == adbench[task, detector], (task, detector)
            assert columns["stratified"] == stratified[task, detector], (task, detector)
        else:                                                      # the seven checked independently
            assert columns["adbench"] is None, (task, detector)
    assert len(guide) == 10 + 6
