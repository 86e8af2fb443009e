"""Every registered detector passes scikit-learn's own estimator checks.

Checks that cannot apply to a detector are listed in ``EXPECTED_FAILURES``
with the reason; nothing else is skipped but the detectors whose optional
dependency is not installed, each shown as skipped with the extra to install.
"""

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import MinMaxScaler
from sklearn.utils.estimator_checks import check_dataframe_column_names_consistency, parametrize_with_checks

import novelty
from novelty.registry import detectors
from novelty.testing import installed_detectors

from .registered import detector_params

#: {detector name: {check name: reason}}
_OWN_TRAINING = ("a perfect memory holds every scan it learned, so each training scan scores 0 against "
                 "itself and none is an outlier of its own training data, whatever the threshold")
_IN_ORDER = ("given the last scans as context, a scan's novelty depends on the scans before it in the batch: "
             "the order of a batch is part of its meaning, by design")
EXPECTED_FAILURES: dict[str, dict[str, str]] = {
    "nearest-memory": {"check_outliers_fit_predict": _OWN_TRAINING, "check_outliers_train": _OWN_TRAINING},
    # PyOD's default model, ECOD, is transductive and scores a batch as PyOD does: a scan's score depends on
    # the scans scored with it (novelty.baselines.pyod_outlier)
    "pyod": {"check_methods_subset_invariance": "ECOD scores a batch against itself, as in PyOD"},
}
#: what a detector given the recent past (delay > 1 or smoothing < 1: the 'explore' preset) cannot pass
_CONTEXT_FAILURES = {"check_methods_sample_order_invariance": _IN_ORDER, "check_methods_subset_invariance": _IN_ORDER}


def _detectors():
    # a detector whose optional dependency is missing is checked where it is installed
    return [novelty.make(name) for name in installed_detectors()]


#: scikit-learn's checks that fit on its own data (a few columns of any values), which a detector reading a
#: layout of its own (the points input: 3 + 3n columns, the ring's in [0, 1]) refuses by design
_LAYOUT_CHECKS = ("check_fit_score_takes_y", "check_estimators_overwrite_params", "check_dont_overwrite_parameters",
                  "check_estimators_fit_returns_self", "check_readonly_memmap_input", "check_n_features_in_after_fitting",
                  "check_positive_only_tag_during_fit", "check_estimators_dtypes", "check_dtype_object",
                  "check_pipeline_consistency", "check_estimators_nan_inf", "check_estimators_pickle",
                  "check_f_contiguous_array_estimator", "check_outliers_fit_predict", "check_outliers_train",
                  "check_classifier_data_not_an_array", "check_methods_sample_order_invariance",
                  "check_methods_subset_invariance", "check_fit2d_1sample", "check_fit2d_1feature", "check_dict_unchanged",
                  "check_fit_idempotent", "check_is_fitted", "check_n_features_in", "check_fit2d_predict1d",
                  "check_fit_check_is_fitted")
_LAYOUT = "reads rows of the points input (3 + 3n columns); scikit-learn's data has other columns"


def _expected_failures(estimator):
    if getattr(estimator, "input_layout", None) is not None:
        return {check: _LAYOUT for check in _LAYOUT_CHECKS}
    name = detectors.name_of(estimator) or ""
    if name == "context" and (estimator.delay > 1 or estimator.smoothing < 1):
        return _CONTEXT_FAILURES
    return EXPECTED_FAILURES.get(name, {})


@parametrize_with_checks(_detectors(), expected_failed_checks=_expected_failures)
def test_sklearn_compatible(estimator, check):
    check(estimator)


def test_clone_pipeline_and_grid_search():
    rng = np.random.default_rng(0)
    X = rng.random((200, 16))
    det = novelty.make("hsom", n_rows=4, n_columns=4)
    twin = clone(det)
    assert twin.get_params()["clusterer__n_rows"] == 4 and twin is not det
    pipe = make_pipeline(MinMaxScaler(), det).fit(X)
    assert set(np.unique(pipe.predict(X))) <= {-1, 1}

    def neg_mean_novelty(estimator, X, y=None):
        return float(np.mean(estimator.score_samples(X)))

    search = GridSearchCV(det, {"clusterer__learning_rate": [0.1, 0.25], "synapse__tau_winner": [3.33, 5.0]},
                          scoring=neg_mean_novelty, cv=2).fit(X)
    assert search.best_params_["clusterer__learning_rate"] in (0.1, 0.25)
    assert search.best_estimator_.clusterer_.learning_rate == search.best_params_["clusterer__learning_rate"]


# every registered detector: one whose optional dependency is missing shows as skipped, naming the extra
@pytest.mark.parametrize("name", detector_params(any_rows=True))
def test_dataframe_column_names_as_scikit_learn_checks_them(name):
    """scikit-learn's own check of ``feature_names_in_`` (not in its default set; needs pandas)."""
    pytest.importorskip("pandas", reason="pandas is not installed (it is not a dependency)")
    check_dataframe_column_names_consistency(name, novelty.make(name))
