"""The scikit-learn scorers on the novelty scale: known values, the search's choice, bad labels."""

import numpy as np
import pytest
from sklearn.ensemble import IsolationForest
from sklearn.metrics import average_precision_score, get_scorer, make_scorer, roc_auc_score
from sklearn.model_selection import GridSearchCV
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import MinMaxScaler

import novelty
from novelty.datasets import load
from novelty.metrics import novelty_average_precision, novelty_of, novelty_roc_auc


class Fixed:
    """A stand-in detector whose novelty of scan i is ``values[i]`` (X holds the indices)."""

    def __init__(self, values):
        self.values = np.asarray(values, dtype=float)

    def novelty(self, X):
        return self.values[np.asarray(X, dtype=int).ravel()]


def _scored(values, y):
    return Fixed(values), np.arange(len(values))[:, None], np.asarray(y)


@pytest.mark.parametrize("values, y, auc", [
    ([0.1, 0.9, 0.5], [0, 1, 0], 1.0),          # the novel scan above both normal ones
    ([0.1, 0.4, 0.5], [0, 1, 0], 0.5),          # above one of two
    ([0.6, 0.4, 0.5], [0, 1, 0], 0.0),          # below both
    ([0.5, 0.5, 0.1], [0, 1, 0], 0.75),         # a tie counts one half: (1 + 0.5) / 2
])
def test_roc_auc_on_three_scans_by_hand(values, y, auc):
    assert novelty_roc_auc(*_scored(values, y)) == auc


def test_average_precision_by_hand():
    # ranked by novelty: novel (P=1/1), normal, novel (P=2/3): AP = (1 + 2/3) / 2
    det, X, y = _scored([0.9, 0.5, 0.4, 0.1], [1, 0, 1, 0])
    assert novelty_average_precision(det, X, y) == pytest.approx(5 / 6, abs=1e-15)


def test_booleans_are_labels():
    assert novelty_roc_auc(*_scored([0.1, 0.9], [False, True])) == 1.0


@pytest.mark.parametrize("y, message", [
    ([0, 0, 0], "only normal"),
    ([1, 1, 1], "only novel"),
    ([0, 1, 2], r"0 \(normal\) or 1 \(novel\); got \[0, 1, 2\]"),
    ([-1, 1, 1], r"scikit-learn's outlier labels.*\(y == -1\)"),
    ([0.0, 0.5, 1.0], r"got \[0.0, 0.5, 1.0\]"),
])
def test_bad_labels_are_refused_with_what_was_expected(y, message):
    for scorer in (novelty_roc_auc, novelty_average_precision):
        with pytest.raises(ValueError, match=message):
            scorer(*_scored([0.1, 0.5, 0.9], y))


def test_no_labels_is_refused():
    with pytest.raises(ValueError, match="needs labels y"):
        novelty_roc_auc(Fixed([0.1]), np.zeros((1, 1)), None)


def test_scikit_learn_sign_is_translated():
    rng = np.random.default_rng(1)
    X = rng.random((60, 3))
    forest = IsolationForest(random_state=0).fit(X[:40])
    assert np.array_equal(novelty_of(forest, X[40:]), -forest.score_samples(X[40:]))
    pipe = make_pipeline(MinMaxScaler(), novelty.make("hsom", n_rows=3, n_columns=3)).fit(X[:40])
    assert np.array_equal(novelty_of(pipe, X[40:]), pipe[-1].novelty(pipe[0].transform(X[40:])))
    with pytest.raises(TypeError, match="neither 'novelty' nor 'score_samples'"):
        novelty_of(MinMaxScaler().fit(X), X)


@pytest.fixture(scope="module")
def door_split():
    """Corridor A learned, then corridor A* (the door opened) scored: 100 + 100 scans, 15 novel."""
    task = load("paper-a-to-a-star", seed=0, train_runs=1, test_runs=1)
    train, test = task.train(), task.test()
    X = np.vstack([train.X, test.X])
    y = np.r_[np.zeros(len(train.X), dtype=int), test.y]
    split = [(np.arange(len(train.X)), np.arange(len(train.X), len(X)))]
    return X, y, split


# the paper's 10 x 10 map against a degenerate 2 x 2 one, which cannot tell the door from the walls
GRID = [{"clusterer__n_rows": [10], "clusterer__n_columns": [10]},
        {"clusterer__n_rows": [2], "clusterer__n_columns": [2]}]


def test_grid_search_with_the_scorer_picks_the_better_map(door_split):
    X, y, split = door_split
    search = GridSearchCV(novelty.make("hsom"), GRID, scoring=novelty_roc_auc, cv=split).fit(X, y)
    assert search.best_params_ == {"clusterer__n_rows": 10, "clusterer__n_columns": 10}
    test = split[0][1]
    for i, params in enumerate(search.cv_results_["params"]):
        det = novelty.make("hsom").set_params(**params).fit(X[split[0][0]])
        assert search.cv_results_["mean_test_score"][i] == roc_auc_score(y[test], det.novelty(X[test]))
    scores = search.cv_results_["mean_test_score"]
    assert max(scores) > 0.7 and min(scores) < 0.5      # clearly better, not a coin toss


def test_scikit_learns_roc_auc_scoring_inverts_on_novelty_labels(door_split):
    """The trap the scorer exists for: ``scoring="roc_auc"`` reads decision_function (higher = normal)."""
    X, y, split = door_split
    train, test = split[0]
    det = novelty.make("hsom").fit(X[train])
    assert get_scorer("roc_auc")(det, X[test], y[test]) == pytest.approx(1 - novelty_roc_auc(det, X[test], y[test]))
    search = GridSearchCV(novelty.make("hsom"), GRID, scoring="roc_auc", cv=split).fit(X, y)
    assert search.best_params_ == {"clusterer__n_rows": 2, "clusterer__n_columns": 2}


def test_average_precision_scorer_equals_scikit_learns_on_the_novelty(door_split):
    X, y, split = door_split
    train, test = split[0]
    det = novelty.make("hsom").fit(X[train])
    assert novelty_average_precision(det, X[test], y[test]) == average_precision_score(y[test], det.novelty(X[test]))


def test_grid_search_without_scoring_is_refused_by_scikit_learn(door_split):
    """Detectors have no ``score`` (as scikit-learn's outlier detectors): the search needs a scorer."""
    X, y, split = door_split
    with pytest.raises(TypeError, match="'score' method"):
        GridSearchCV(novelty.make("hsom"), GRID, cv=split).fit(X, y)


def test_make_scorer_traps_the_docstring_names(door_split):
    """``make_scorer`` reads ``predict`` (-1 novel) or ``decision_function`` (higher = normal): both invert."""
    X, y, split = door_split
    train, test = split[0]
    det = novelty.make("hsom").fit(X[train])
    auc = novelty_roc_auc(det, X[test], y[test])
    flagged = (det.predict(X[test]) == -1).astype(int)
    assert make_scorer(roc_auc_score)(det, X[test], y[test]) == pytest.approx(1 - roc_auc_score(y[test], flagged))
    by_decision = make_scorer(roc_auc_score, response_method="decision_function")
    assert by_decision(det, X[test], y[test]) == pytest.approx(1 - auc)
    negated = make_scorer(roc_auc_score, response_method="decision_function", greater_is_better=False)
    assert negated(det, X[test], y[test]) == pytest.approx(auc - 1)   # the right order, a wrong-looking score
