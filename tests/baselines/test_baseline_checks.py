"""scikit-learn's estimator checks and the project's conformance suite on the baselines.

The registered baselines with their defaults are already checked through the
registry (tests/test_sklearn_compat.py, tests/testing/test_conformance.py); here the
other configurations: the batch variants, other covariance forms and
bandwidth rules, a small map, and the generic adapter around estimators
that are not registered; and a point far from the training data is the
most novel for every density and distance baseline.
"""

import pytest
from sklearn.ensemble import IsolationForest
from sklearn.linear_model import SGDOneClassSVM
from sklearn.utils.estimator_checks import parametrize_with_checks

from novelty.baselines import (
    AutoencoderFilter,
    GaussianMixtureDetector,
    KohonenNoveltyFilter,
    ParzenDetector,
    SklearnOutlierDetector,
    SOMDistance,
)
from novelty.clusterers.som import SOM
from novelty.testing import conformance_checks

SAVEABLE = [
    KohonenNoveltyFilter(method="pca", n_components=2),
    KohonenNoveltyFilter(learning_rate=1.0, n_epochs=2),
    GaussianMixtureDetector(n_components=2, covariance_type="diag"),
    GaussianMixtureDetector(max_components=3, covariance_type="spherical"),
    ParzenDetector(bandwidth="silverman"),
    ParzenDetector(bandwidth=0.5),
    SOMDistance(clusterer=SOM(n_rows=3, n_columns=3, init="sample")),
    AutoencoderFilter(hidden_layer_sizes=(3,), activation="relu", max_iter=100),
]
GENERIC = [
    SklearnOutlierDetector(SGDOneClassSVM(random_state=0)),
    SklearnOutlierDetector(IsolationForest(n_estimators=20, random_state=0)),
]


@parametrize_with_checks(SAVEABLE + GENERIC)
def test_sklearn_checks(estimator, check):
    check(estimator)


def _conformance():
    for est in SAVEABLE:
        for check in conformance_checks(est):
            yield pytest.param(check, id=f"{est!r}:{check.__name__}")


@pytest.mark.parametrize("check", list(_conformance()))
def test_conformance_of_other_configurations(check):
    check()


@pytest.mark.parametrize("det", [GaussianMixtureDetector(n_components=3), ParzenDetector(), SOMDistance(n_epochs=3),
                                 SOMDistance(clusterer=SOM(n_rows=4, n_columns=4, init="sample"))],
                         ids=["gmm", "parzen", "som-distance", "som-distance-sample"])
def test_a_far_point_is_more_novel_than_every_training_point(det, blobs, far):
    det.fit(blobs)
    assert det.raw_novelty(far)[0] > det.raw_novelty(blobs).max()
    assert det.novelty(far)[0] > det.novelty(blobs).max()
    assert det.predict(far)[0] == -1
