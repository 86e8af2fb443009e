"""The paper's sonar preprocessing as a scikit-learn transformer."""

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.pipeline import make_pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks

import novelty
from novelty.sonar import preprocess
from novelty.sonar.preprocessor import SonarPreprocessor

# inf is a range (no echo) here, not bad input; scikit-learn's check expects it refused
EXPECTED_FAILED = {"check_estimators_nan_inf": "inf is a valid range (no echo); NaN is refused"}


@parametrize_with_checks([SonarPreprocessor(), SonarPreprocessor(threshold=2.5)],
                         expected_failed_checks=lambda est: EXPECTED_FAILED)
def test_scikit_learn_checks(estimator, check):
    check(estimator)


def test_hand_computed_ranges_with_no_echo():
    out = SonarPreprocessor(threshold=2.0).fit([[1.0, 1.0, 1.0]]).transform([[0.5, 2.0, np.inf]])
    assert out.tolist() == [[0.75, 0.0, 0.0]]


def test_the_same_numbers_as_the_function_and_the_files_reader():
    X = np.random.default_rng(0).uniform(0, 6, (50, 16))
    np.testing.assert_array_equal(SonarPreprocessor().fit_transform(X), preprocess(X))


def test_in_a_pipeline_before_a_detector_with_its_parameters_reachable():
    X = np.random.default_rng(1).uniform(0, 6, (40, 16))
    pipe = make_pipeline(SonarPreprocessor(), novelty.make("hsom", n_rows=3))
    assert pipe.get_params()["sonarpreprocessor__threshold"] == 4.0
    pipe.set_params(sonarpreprocessor__threshold=3.0)
    scores = clone(pipe).fit(X).score_samples(X)
    expected = novelty.make("hsom", n_rows=3).fit(preprocess(X, 3.0)).score_samples(preprocess(X, 3.0))
    np.testing.assert_array_equal(scores, expected)


@pytest.mark.parametrize("threshold", [0, -1.0, "4", float("inf")])
def test_a_bad_threshold_is_refused_in_fit(threshold):
    with pytest.raises(ValueError, match="The 'threshold' parameter of SonarPreprocessor must be a float in "
                                         r"\(0, inf\)"):
        SonarPreprocessor(threshold=threshold).fit([[1.0]])


def test_nan_is_refused():
    with pytest.raises(ValueError, match="expects ranges in metres .* got NaN"):
        SonarPreprocessor().fit([[np.nan]])
