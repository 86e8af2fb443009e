"""The components' base: the engine as the one writer of a fitted filter's parts."""

import contextlib
import copy
import warnings

import numpy as np
import pytest

import novelty
from novelty._kernels import reference_loops

X = np.random.default_rng(0).uniform(0.0, 1.0, (120, 5))


def test_setting_a_parameter_of_a_fitted_part_warns_and_says_what_to_do_instead():
    det = novelty.make("hsom", n_rows=2, n_columns=2).fit(X)
    with pytest.warns(FutureWarning, match=r"SOM\.learning_rate on a fitted part.*set_params\("
                                           r"clusterer__learning_rate=\.\.\.\)\) and fit again"):
        det.clusterer_.learning_rate = 0.3
    assert det.clusterer_.learning_rate == 0.3  # deprecated, not refused yet
    with pytest.warns(FutureWarning, match=r"StanleySynapse\.alpha on a fitted part.*synapse__alpha"):
        det.synapse_.set_params(alpha=1.5)


def test_setting_learned_state_of_a_fitted_part_warns_to_refit():
    det = novelty.make("hsom", n_rows=2, n_columns=2).fit(X)
    with pytest.warns(FutureWarning, match=r"StanleySynapse\.efficacy_ on a fitted part.*fit again"):
        det.synapse_.efficacy_ = np.ones(4)


def test_templates_unfitted_parts_and_private_scratch_do_not_warn():
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)
        det.clusterer.learning_rate = 0.3  # a template: the next fit builds from it
        det.fit(X)
        det.clusterer.learning_rate = 0.25
        det.clusterer_._scratch = 1  # not a parameter nor learned state
        novelty.make("hsom").clusterer.n_rows = 3


@pytest.mark.parametrize("kernels", [True, False])
@pytest.mark.parametrize("name,params", [
    ("hsom", {}),
    ("gng-stanley", {}),  # units added and removed
    ("gwr-novelty", {"novelty_rule": "mismatch", "activity_threshold": "auto"}),  # each scale given
])
def test_the_engines_own_writes_do_not_warn(kernels, name, params):
    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)
        with contextlib.nullcontext() if kernels else reference_loops():
            det = novelty.make(name, **params).fit(X[:60])
            det.stream(X[60:])
            det.novelty(X)
            for x in X[:10]:
                det.score_learn_one(x)
                det.score_one(x)
            copy.deepcopy(det).partial_fit(X[:30])
