"""Bad parameters: a message naming the parameter and its range, and the model exactly as it was."""

import numbers

import numpy as np
import pytest

import novelty
from novelty._validation import Bounds, Interval, Options
from novelty.registry import clusterers

from .model_state import N_FEATURES, assert_equal_deep, fitted, snapshot


@pytest.mark.parametrize(
    "params, message",
    [
        ({"threshold": "high"}, r"The 'threshold' parameter of HabituatingFilter must be a float in \(-inf, inf\)\. Got 'high' instead\."),
        ({"n_epochs": 0}, r"The 'n_epochs' parameter of HabituatingFilter must be an int in \[1, inf\)\. Got 0 instead\."),
        ({"stimulus": -1.0}, r"The 'stimulus' parameter of HabituatingFilter must be a float in \[0, inf\)"),
        ({"learning_rate": 2.0}, r"The 'learning_rate' parameter of SOM must be a float in \[0, 1\]\. Got 2\.0 instead\."),
        ({"n_rows": 0}, r"The 'n_rows' parameter of SOM must be an int in \[1, inf\)"),
        ({"tau_winner": -3.0}, r"The 'tau_winner' parameter of StanleySynapse must be a float in \(0, inf\)"),
        ({"tau_neighbour": 0.5}, r"The 'tau_neighbour' parameter of StanleySynapse must be >= alpha"),
        ({"others": "forgetful"}, r"The 'others' parameter of StanleySynapse must be one of 'hold', 'forget'"),
    ],
)
@pytest.mark.parametrize("method", ["fit", "partial_fit", "learn_one"])
def test_invalid_parameters_name_the_parameter_and_range_and_leave_it_unfitted(params, message, method):
    det = novelty.make("hsom", n_rows=2, n_columns=2, **{k: v for k, v in params.items() if k != "n_rows"})
    if "n_rows" in params:
        det.set_params(clusterer__n_rows=params["n_rows"])
    X = np.full((2, N_FEATURES), 0.5)
    with pytest.raises(ValueError, match=message):
        getattr(det, method)(X[0] if method == "learn_one" else X)
    assert not hasattr(det, "n_features_in_") and not hasattr(det, "clusterer_")
    assert not hasattr(det, "synapse_")


def test_a_refit_with_invalid_parameters_keeps_the_fitted_model():
    det = fitted()
    before = snapshot(det)
    det.synapse.set_params(tau_winner=0.1)  # the specification, not the fitted synapse_
    with pytest.raises(ValueError, match="'tau_winner' parameter of StanleySynapse"):
        det.fit(np.zeros((3, N_FEATURES)))
    after = snapshot(det)
    after["detector"].pop("synapse"), before["detector"].pop("synapse")
    assert_equal_deep(before, after)


def test_component_given_as_the_wrong_type_is_named():
    det = novelty.make("habituating", clusterer=novelty.StanleySynapse(), synapse="stanley")
    with pytest.raises(ValueError, match=r"The 'clusterer' parameter of HabituatingFilter must be a clusterer name or a Clusterer instance"):
        det.fit(np.zeros((2, 2)))


# ------------------------------------------------------------- the checks
@pytest.mark.parametrize(
    "rule, value, ok",
    [
        (Interval(numbers.Integral, 1, None), 1, True),
        (Interval(numbers.Integral, 1, None), True, False),  # bool is not an int here
        (Interval(numbers.Integral, 1, None), np.int64(3), True),
        (Interval(numbers.Integral, 1, None), 2.0, False),
        (Interval(numbers.Real, 0, 1), 1.0, True),
        (Interval(numbers.Real, 0, 1, closed="left"), 1.0, False),
        (Interval(numbers.Real, 0, None, closed="neither"), 0.0, False),
        (Interval(numbers.Real, None, None), float("inf"), False),
        (Interval(numbers.Real, None, None), float("nan"), False),
        (Interval(numbers.Real, 0, None, allow_none=True), None, True),
        (Interval(numbers.Real, 0, None), None, False),
        (Options(("a", "b")), "a", True),
        (Options(("a", "b")), ["a"], False),
        (Options(("a", "b")), "c", False),
    ],
)
def test_rules_accept_exactly_their_values(rule, value, ok):
    assert rule.accepts(value) is ok


def test_rule_descriptions():
    assert Interval(numbers.Integral, 1, None).describe() == "an int in [1, inf)"
    assert Interval(numbers.Real, 0, 1).describe() == "a float in [0, 1]"
    assert Interval(numbers.Real, 0, None, closed="neither", allow_none=True).describe() == "a float in (0, inf) or None"
    assert Options(("hold", "forget")).describe() == "one of 'hold', 'forget'"


# ------------------------------------------------------------ init_range
@pytest.mark.parametrize("value, accepted", [
    ((0.0, 1.0), True), ([-2, 3], True), ((np.float32(0.5), 2), True),
    ((1.0, 0.0), False), ((0.5, 0.5), False), ((True, 2.0), False), ((0.0, True), False), ((False, True), False),
    ((0.0, float("inf")), False), ((float("nan"), 1.0), False), ((0.0,), False), ((0.0, 1.0, 2.0), False),
    ("ab", False), (None, False), ((0.0, "1"), False),
])
def test_the_bounds_rule(value, accepted):
    assert Bounds().accepts(value) is accepted


INIT_RANGE = [name for name in clusterers.names() if "init_range" in (clusterers.parameters(name) or [])]


def test_every_builtin_clusterer_with_an_initial_range_is_checked():
    assert {"som", "gng", "gwr", "online-kmeans"} <= set(INIT_RANGE)


@pytest.mark.parametrize("name", INIT_RANGE)
@pytest.mark.parametrize("bad", [(False, 1.0), (0.0, True), (1.0, 0.0), (0.0, float("inf"))])
def test_every_clusterers_initial_range_is_one_check_refusing_booleans(name, bad):
    net = clusterers.make(name, init_range=bad, init="uniform")
    with pytest.raises(ValueError, match=rf"^The 'init_range' parameter of {type(net).__name__} must be a pair "
                                         r"\(low, high\) of finite floats with low < high\. Got "):
        net.initialize(np.zeros((4, 2)), random_state=0)
    assert not hasattr(net, "weights_")
