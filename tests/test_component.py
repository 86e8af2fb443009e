"""The components' base: the engine as the one writer of a fitted filter's parts."""

import contextlib
import copy
import warnings

import numpy as np
import pytest

import novelty
from novelty import FittedPartError
from novelty._kernels import reference_loops

X = np.random.default_rng(0).uniform(0.0, 1.0, (120, 5))

ENGINES = [pytest.param(contextlib.nullcontext, id="compiled"), pytest.param(reference_loops, id="reference")]


def test_setting_a_parameter_of_a_fitted_part_raises_and_says_what_to_do_instead():
    det = novelty.make("hsom", n_rows=2, n_columns=2).fit(X)
    before, rate = det.novelty(X), det.clusterer_.learning_rate
    with pytest.raises(FittedPartError, match=r"SOM\.learning_rate cannot be set on a fitted part.*set_params\("
                                              r"clusterer__learning_rate=\.\.\.\)\) and fit again"):
        det.clusterer_.learning_rate = 0.3
    assert det.clusterer_.learning_rate == rate  # left as it was
    with pytest.raises(FittedPartError, match=r"StanleySynapse\.alpha cannot be set.*synapse__alpha"):
        det.synapse_.set_params(alpha=1.5)
    assert det.synapse_.alpha == novelty.make("hsom").synapse.alpha
    with pytest.raises(AttributeError):  # FittedPartError is an AttributeError, as for any read-only attribute
        del det.synapse_.efficacy_
    np.testing.assert_array_equal(det.novelty(X), before)


def test_setting_learned_state_of_a_fitted_part_raises_to_refit():
    det = novelty.make("hsom", n_rows=2, n_columns=2).fit(X)
    with pytest.raises(FittedPartError, match=r"StanleySynapse\.efficacy_ cannot be set.*fit again"):
        det.synapse_.efficacy_ = np.ones(4)
    assert not np.array_equal(det.synapse_.efficacy_, np.ones(4))


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", ["hsom", "gng-stanley", "gwr-novelty"])
def test_a_fitted_part_s_learned_arrays_are_read_only(engine, name):
    with engine():
        det = novelty.make(name).fit(X[:60])
        before = det.novelty(X)
        for part in (det.clusterer_, det.synapse_):
            for attr, value in vars(part).items():
                if type(value) is np.ndarray and attr.endswith("_") and not attr.startswith("_"):
                    assert not value.flags.writeable, f"{type(part).__name__}.{attr}"
                    with pytest.raises(ValueError, match="read-only"):
                        value[...] = 0
        np.testing.assert_array_equal(det.novelty(X), before)
        det.partial_fit(X[60:])  # the engine still writes them
        assert not det.clusterer_.weights_.flags.writeable


def test_a_read_only_array_that_was_not_the_part_s_stays_read_only(tmp_path):
    # a caller's read-only array (a memory map's, say) is copied by the engine that writes, not unlocked
    det = novelty.make("hsom", n_rows=2, n_columns=2).fit(X)
    det.save(tmp_path / "det.npz")
    loaded = novelty.load(tmp_path / "det.npz")
    theirs = np.array(loaded.synapse_.efficacy_)
    theirs.setflags(write=False)
    vars(loaded.synapse_)["efficacy_"] = theirs  # as a memory-mapped load would hold it
    with reference_loops():
        loaded.partial_fit(X[:10])
    assert not theirs.flags.writeable
    assert loaded.synapse_.efficacy_ is not theirs


def test_templates_unfitted_parts_and_private_scratch_may_be_set():
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    det.clusterer.learning_rate = 0.3  # a template: the next fit builds from it
    det.fit(X)
    det.clusterer.learning_rate = 0.25
    det.clusterer_._scratch = 1  # not a parameter nor learned state
    novelty.make("hsom").clusterer.n_rows = 3
    assert det.clusterer.learning_rate == 0.25 and det.clusterer_._scratch == 1


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name,params", [
    ("hsom", {}),
    ("gng-stanley", {}),  # units added and removed
    ("gwr-novelty", {"novelty_rule": "mismatch", "activity_threshold": "auto"}),  # each scale given
])
def test_the_engines_own_writes_pass(engine, name, params):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with engine():
            det = novelty.make(name, **params).fit(X[:60])
            det.stream(X[60:])
            det.novelty(X)
            for x in X[:10]:
                det.score_learn_one(x)
                det.score_one(x)
            twin = copy.deepcopy(det)
            twin.partial_fit(X[:30])
            det.partial_fit(X[:30])
            np.testing.assert_array_equal(twin.novelty(X), det.novelty(X))
