"""Bad parameters: a message naming the parameter and its range, and the model exactly as it was."""

import numbers

import numpy as np
import pytest

import novelty
from novelty._validation import Bounds, Interval, Options, validate_parameters
from novelty.registry import clusterers
from tests.damaged import damaging

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


# -------------------------------------- parameters changed between two calls
@pytest.mark.parametrize("name, bad, message", [
    ("stimulus", -1.0, r"'stimulus' parameter of HabituatingFilter must be a float in \[0, inf\)"),
    ("n_epochs", True, r"'n_epochs' parameter of HabituatingFilter must be an int in \[1, inf\)\. Got True"),
    ("n_epochs", 1.0, r"'n_epochs' parameter of HabituatingFilter must be an int"),
    ("threshold", float("nan"), r"'threshold' parameter of HabituatingFilter must be a float"),
    ("novelty_rule", "mismatched", r"'novelty_rule' parameter of HabituatingFilter must be one of"),
    ("contamination", 0.7, r"'contamination' parameter of HabituatingFilter must be"),
    ("clusterer", novelty.StanleySynapse(), r"'clusterer' parameter of HabituatingFilter must be a clusterer"),
])
@pytest.mark.parametrize("how", ["attribute", "set_params"])
def test_a_parameter_changed_after_a_checked_call_is_checked_again(name, bad, message, how):
    # the checks of the calls before remember what passed; a change is still refused
    det = fitted()
    X = np.full((2, N_FEATURES), 0.5)
    for _ in range(2):
        det.partial_fit(X)
        det.learn_one(X[0])
    before = snapshot(det)
    if how == "attribute":
        setattr(det, name, bad)
    else:
        det.set_params(**{name: bad})
    for method in ("partial_fit", "stream"):
        with pytest.raises(ValueError, match=message):
            getattr(det, method)(X)
    after = snapshot(det)
    after["detector"][name] = before["detector"][name]
    for cache in ("_parts_changed", "_engine"):  # set_params records a new part, drops the compiled loop
        if cache in before["detector"]:
            after["detector"][cache] = before["detector"][cache]
    assert_equal_deep(before, after)


def test_a_valid_parameter_set_back_passes_and_a_bad_one_again_fails():
    det = fitted()
    X = np.full((2, N_FEATURES), 0.5)
    for value, ok in [(1.0, True), (-1.0, False), (1.05, True), (-1.0, False), (-1.0, False), (1.0, True)]:
        det.stimulus = value
        if ok:
            det.partial_fit(X)
        else:
            with pytest.raises(ValueError, match="'stimulus' parameter"):
                det.partial_fit(X)


class _Ranged(novelty.HabituatingFilter):
    """A detector with a list parameter, which can change without being set again."""

    _parameter_rules = {**novelty.HabituatingFilter._parameter_rules, "window": Bounds()}

    def __init__(self, window=None, **params):
        super().__init__(**params)
        self.window = window


def test_a_list_changed_in_place_is_checked_again():
    owner = _Ranged(window=[0.0, 1.0])
    validate_parameters(owner)
    validate_parameters(owner)
    owner.window[1] = -1.0  # the same list, now refused
    with pytest.raises(ValueError, match=r"The 'window' parameter of _Ranged must be a pair"):
        validate_parameters(owner)


def test_a_rule_of_another_kind_is_asked_every_time():
    calls = []

    class Counting:
        def accepts(self, value):
            calls.append(value)
            return value != "no"

        def describe(self):
            return "anything but 'no'"

    owner = _Ranged(window=(0.0, 1.0))
    owner.kind = "yes"
    rules = {"kind": Counting(), "window": Bounds()}
    validate_parameters(owner, rules)
    validate_parameters(owner, rules)
    assert calls == ["yes", "yes"]
    owner.kind = "no"
    with pytest.raises(ValueError, match=r"'kind' parameter of _Ranged must be anything but 'no'\. Got 'no'"):
        validate_parameters(owner, rules)


def test_changed_rules_are_applied_to_a_value_that_passed_the_old_ones():
    owner = _Ranged(window=(0.0, 1.0))
    owner.level = 5
    rules = {"level": Interval(numbers.Integral, 0, 10)}
    validate_parameters(owner, rules)
    rules["level"] = Interval(numbers.Integral, 0, 3)  # the same dict, changed in place
    with pytest.raises(ValueError, match=r"'level' parameter of _Ranged must be an int in \[0, 3\]"):
        validate_parameters(owner, rules)


# ------------------------------------------- a part's parameter set directly after fitting
@pytest.mark.parametrize("method", ["score_learn_one", "partial_fit", "stream"])
def test_a_part_parameter_set_directly_after_fitting_is_noticed_as_set_params_notes_it(method):
    """``det.synapse.alpha = x`` (the part the next fit builds from) refuses learning on, as
    ``set_params(synapse__alpha=x)`` does, and an invalid value is named first; set back, the
    detector learns on."""
    det = fitted()
    X = np.full((2, N_FEATURES), 0.5)
    det.learn_one(X[0])
    before = snapshot(det)
    arg = X[0] if method == "score_learn_one" else X
    det.synapse.alpha = 1.5
    with pytest.raises(ValueError, match=r"^synapse__alpha changed after fitting"):
        getattr(det, method)(arg)
    det.synapse.alpha = -1.0
    with pytest.raises(ValueError, match=r"^The 'alpha' parameter of StanleySynapse must be a float"):
        getattr(det, method)(arg)
    det.synapse.alpha = novelty.make("hsom").synapse.alpha  # set back
    after = snapshot(det)
    after["detector"]["_parts_changed"] = before["detector"]["_parts_changed"]
    assert_equal_deep(before, after)
    getattr(det, method)(arg)


@pytest.mark.parametrize("method", ["score_learn_one", "partial_fit"])
def test_an_invalid_parameter_set_on_a_fitted_part_is_refused_with_its_rule(method):
    """A fitted part's parameter cannot be set (``FittedPartError``); one set all the same, past
    the lock (tests.damaged), is checked against its rule at the next call, which leaves the
    model as it was; a valid value is learned with."""
    det = fitted()
    X = np.full((2, N_FEATURES), 0.5)
    det.learn_one(X[0])
    arg = X[0] if method == "score_learn_one" else X
    before = snapshot(det)
    with pytest.raises(novelty.FittedPartError, match="synapse__alpha"):
        det.synapse_.alpha = -1.0
    assert_equal_deep(before, snapshot(det))
    with damaging(det):
        det.synapse_.alpha = -1.0
    with pytest.raises(ValueError, match=r"^The 'alpha' parameter of StanleySynapse must be a float"):
        getattr(det, method)(arg)
    with damaging(det):
        det.clusterer_.learning_rate = 2.0
        det.synapse_.alpha = before["synapse_"]["alpha"]
    with pytest.raises(ValueError, match=r"^The 'learning_rate' parameter of SOM must be a float in \[0, 1\]"):
        getattr(det, method)(arg)
    after = snapshot(det)
    after["clusterer_"]["learning_rate"] = before["clusterer_"]["learning_rate"]
    assert_equal_deep(before, after)
    with damaging(det):
        det.clusterer_.learning_rate = 0.5
    getattr(det, method)(arg)
    assert det.clusterer_.learning_rate == 0.5
