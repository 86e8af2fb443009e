"""Short parameter names routed to the part that takes them, by make, from_params and set_params."""

import re

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.metrics import roc_auc_score
from sklearn.model_selection import GridSearchCV, StratifiedKFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import MinMaxScaler

import novelty
from novelty.clusterers.som import SOM
from novelty.filter import HabituatingFilter
from novelty.habituation.stanley import StanleySynapse
from novelty.registry import InvalidParameterError


def test_from_params_routes_flat_names():
    det = novelty.make("hsom", n_rows=5, alpha=1.2, threshold=0.3, method="exact", random_state=4)
    assert det.clusterer.n_rows == 5 and det.clusterer.n_columns == 10
    assert det.synapse.alpha == 1.2 and det.synapse.method == "exact"
    assert det.threshold == 0.3 and det.random_state == 4
    assert det.synapse.tau_winner == 3.33  # untouched


def test_from_params_routes_prefixed_names():
    det = novelty.make("habituating", clusterer="som", synapse="stanley",
                       clusterer__radius=2, synapse__tau_winner=5.0)
    assert det.clusterer.radius == 2 and det.synapse.tau_winner == 5.0


class RateSynapse(StanleySynapse):
    """A synapse that (oddly) also has a learning rate, to make a name ambiguous."""

    def __init__(self, tau_winner=3.33, learning_rate=0.5):
        super().__init__(tau_winner=tau_winner)
        self.learning_rate = learning_rate


def test_from_params_refuses_an_ambiguous_name_and_accepts_the_prefixed_one():
    with pytest.raises(InvalidParameterError, match=r"'learning_rate' is taken by both .*clusterer__learning_rate"):
        HabituatingFilter.from_params(clusterer="som", synapse=RateSynapse(), learning_rate=0.3)
    det = HabituatingFilter.from_params(clusterer="som", synapse=RateSynapse(), synapse__learning_rate=0.3)
    assert det.synapse.learning_rate == 0.3 and det.clusterer.learning_rate == 0.25


def test_from_params_with_an_instance_clones_it():
    som = SOM(n_rows=3)
    det = HabituatingFilter.from_params(clusterer=som, n_columns=2)
    assert (det.clusterer.n_rows, det.clusterer.n_columns) == (3, 2)
    assert som.n_columns == 10


@pytest.mark.parametrize(
    "params, expected",
    [
        ({"n_row": 5}, [r"'n_row' \(did you mean 'n_rows'\?\)", "n_rows", "tau_winner", "threshold"]),
        ({"bogus": 1}, [r"Unknown parameter 'bogus'", "learning_rate", "alpha", "n_epochs"]),
        ({"clusterer__tau_winner": 5}, [r"'tau_winner'", r"clusterer 'som'", "n_rows", "radius"]),
        ({"synapse__n_rows": 5}, [r"'n_rows'", r"synapse 'stanley'", "tau_winner", "alpha"]),
    ],
)
def test_unknown_names_list_the_valid_ones(params, expected):
    with pytest.raises(InvalidParameterError) as info:
        novelty.make("hsom", **params)
    for pattern in expected:
        assert re.search(pattern, str(info.value)), (pattern, str(info.value))
    assert isinstance(info.value, TypeError) and isinstance(info.value, ValueError)


def test_set_params_takes_a_components_short_name_as_make_does():
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    assert det.set_params(alpha=1.2, n_rows=3, threshold=0.4) is det
    assert (det.synapse.alpha, det.clusterer.n_rows, det.threshold) == (1.2, 3, 0.4)
    params = det.get_params()
    assert "alpha" not in params and params["synapse__alpha"] == 1.2  # each parameter reported once
    assert clone(det).get_params()["synapse__alpha"] == 1.2
    assert repr(clone(det)) == repr(novelty.make("hsom", n_rows=3, n_columns=2, alpha=1.2, threshold=0.4))


def test_a_grid_over_a_short_name_searches_the_component():
    rng = np.random.default_rng(0)
    X = np.vstack([rng.uniform(0.0, 0.2, (20, 2)), rng.uniform(0.8, 1.0, (4, 2))])
    y = np.r_[np.zeros(20), np.ones(4)]
    auc = lambda est, X, y: roc_auc_score(y, -est.score_samples(X))  # noqa: E731
    search = GridSearchCV(novelty.make("hsom", n_rows=2, n_columns=2), {"alpha": [1.05, 1.2]},
                          scoring=auc, cv=StratifiedKFold(2), error_score="raise").fit(X, y)
    assert search.best_estimator_.synapse.alpha in (1.05, 1.2)
    assert np.isfinite(search.cv_results_["mean_test_score"]).all()
    pipe = make_pipeline(MinMaxScaler(), novelty.make("hsom", n_rows=2, n_columns=2))
    assert pipe.set_params(habituatingfilter__tau_winner=5.0)[-1].synapse.tau_winner == 5.0


def test_set_params_refuses_an_ambiguous_short_name_as_make_does():
    det = HabituatingFilter.from_params(clusterer="som", synapse=RateSynapse())
    with pytest.raises(ValueError, match=r"'learning_rate' is taken by both the clusterer and the synapse; "
                                         r"write clusterer__learning_rate or synapse__learning_rate"):
        det.set_params(learning_rate=0.3)
    assert det.synapse.learning_rate == 0.5 and det.clusterer.learning_rate == 0.25


def test_set_params_names_the_full_name_of_an_unknown_one():
    det = novelty.make("hsom")
    with pytest.raises(ValueError, match=r"Unknown parameter 'alpah' \(did you mean 'alpha', that is "
                                         r"'synapse__alpha'\?\) for HabituatingFilter\. Valid parameters: "
                                         r".*synapse__alpha"):
        det.set_params(alpah=1.2)


def test_set_params_by_short_name_needs_the_component_as_an_instance():
    det = HabituatingFilter(synapse="stanley")
    with pytest.raises(ValueError, match=r"'alpha' is a parameter of the synapse 'stanley', given by name; "
                                         r"set synapse= to an instance"):
        det.set_params(alpha=1.2)
    assert det.set_params(synapse=StanleySynapse(), alpha=1.2).synapse.alpha == 1.2
