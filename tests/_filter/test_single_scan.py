"""One scan at a time: score_learn_one and score_one in one engine call, as the general path."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import novelty
from novelty import _kernels

from .._kernels.kernel_helpers import assert_same_filter, corridor, reference_only

pytestmark = pytest.mark.skipif(not _kernels.kernels_enabled(), reason="numba kernels unavailable")


def _counting_single_scans(det, monkeypatch, method="learn_one"):
    """What the engine's single-scan call (``learn_one`` or ``score_one``) answered, a list that
    grows: True for a scan it took, False for one it left to the general path."""
    answers = []
    engine = det._current_engine()  # chosen once the kernels are ready (the one of the fit waited for them)
    original = getattr(engine, method)

    def counting(*args):
        done = original(*args)
        answers.append(done)
        return done

    monkeypatch.setattr(engine, method, counting)
    return answers


def test_single_scans_learn_and_score_compiled_as_the_reference(monkeypatch):
    X = corridor(80, n_features=5, seed=4)
    fast, slow = novelty.make("hsom", n_rows=4, n_columns=4), novelty.make("hsom", n_rows=4, n_columns=4)
    fast.fit(X[:10])
    assert _kernels.wait(fast.clusterer_, fast.synapse_) is not None and _kernels.wait() is not None
    learned = _counting_single_scans(fast, monkeypatch)
    scored = _counting_single_scans(fast, monkeypatch, "score_one")
    got = [fast.score_learn_one(x) for x in X[10:40]] + [fast.learn_one(x).score_one(x) for x in X[40:]]
    with reference_only():
        slow.fit(X[:10])
        expected = [slow.score_learn_one(x) for x in X[10:40]] + [slow.learn_one(x).score_one(x) for x in X[40:]]
    assert learned == [True] * 70 and scored == [True] * 40  # all by the single-scan calls
    np.testing.assert_array_equal(got, expected)
    assert_same_filter(fast, slow)


NEAR_BOUND = np.full(4, 0.5e100 * (1 - 1e-7))  # within the bound, not within the drivers' margin


@pytest.mark.parametrize("method", ["score_learn_one", "score_one"])
@pytest.mark.parametrize("scan, message", [
    (np.array([0.5, np.nan, 0.5, 0.5]), r"^Input x for HabituatingFilter contains NaN or infinity\.$"),
    (np.array([0.5, 0.5, -np.inf, 0.5]), r"^Input x for HabituatingFilter contains NaN or infinity\.$"),
    (np.full(4, 1e155), r"^Input x for HabituatingFilter has a scan of Euclidean norm above 1e\+100"),
    (np.full(4, 0.6e100), r"^Input x for HabituatingFilter has a scan of Euclidean norm above 1e\+100"),
    (np.full(5, 0.5), r"^x has 5 features, but HabituatingFilter is expecting 4 features as input\.$"),
    (np.full(3, 0.5), r"^x has 3 features, but HabituatingFilter is expecting 4 features as input\.$"),
    (NEAR_BOUND, None),
])
def test_the_single_scan_calls_leave_every_refusal_to_the_general_check(monkeypatch, method, scan, message):
    """The compiled calls' own check of a scan lets through only what the general check
    accepts; on anything else nothing is learned and the general path says what is wrong, as
    before."""
    X = corridor(20, n_features=4, seed=5)
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(X)
    assert _kernels.wait(det.clusterer_, det.synapse_) is not None and _kernels.wait() is not None
    slow = copy.deepcopy(det)
    answers = _counting_single_scans(det, monkeypatch, "learn_one" if method == "score_learn_one" else method)
    det.score_learn_one(X[0])
    det.score_one(X[1])
    with reference_only():
        slow.score_learn_one(X[0])
    assert answers == [True]
    if message is None:
        got = getattr(det, method)(scan)
        with reference_only():
            expected = getattr(slow, method)(scan)
        assert got == expected
    else:
        with pytest.raises(ValueError, match=message):
            getattr(det, method)(scan)
    assert answers == [True, False]  # the compiled call refused it (and learned nothing)
    assert_same_filter(det, slow)

