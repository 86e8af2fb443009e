"""The engine interface: one freshness check, by counts of changes, for both engines."""

from __future__ import annotations

import contextlib
import copy
import pickle

import numpy as np
import pytest

import novelty
from novelty._component import StateError
from novelty._kernels import reference_loops
from novelty import _kernels
from novelty._kernels.engine import CompiledEngine
from novelty._kernels.interface import CheckedCopy

from tests.damaged import damaging

from .kernel_helpers import corridor


@pytest.mark.parametrize("reference", [False, True])
def test_an_engine_holds_the_parts_until_one_is_set(reference):
    with reference_loops() if reference else contextlib.nullcontext():
        det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
        engine = det._current_engine()
        det.stream(corridor(10, n_features=4, seed=1))  # its own writes, taken as seen
        assert engine.holds() and det._current_engine() is engine
        with damaging(det):
            det.synapse_.tau_winner = 5.0
        assert not engine.holds()
        assert det._current_engine() is not engine


def test_fresh_also_watches_what_the_owner_gave():
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
    engine = det._current_engine()
    assert engine.holds() and not engine.fresh()  # nothing confirmed by the owner yet
    engine.watch(det, det.synapse)
    assert engine.fresh()
    det.threshold = 0.3  # the owner: fresh no longer, but the engine still holds the parts
    assert engine.holds() and not engine.fresh()
    engine.watch(det, det.synapse)
    det.synapse.alpha = 1.2  # a template the owner watches
    assert engine.holds() and not engine.fresh()


def test_a_copy_or_a_pickle_makes_its_own_engine():
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
    engine = det._current_engine()
    copied = copy.deepcopy(det)
    assert isinstance(copied._engine, CheckedCopy) and copied._engine.clusterer is copied.clusterer_
    assert copied._current_engine() is not engine and copied._current_engine().clusterer is copied.clusterer_
    assert pickle.loads(pickle.dumps(det))._engine is None
    with damaging(det):
        det.synapse_.alpha = 1.2  # set after the engine read it: a copy's state is not taken as checked
    assert copy.deepcopy(det)._engine is None


def _counting_checks(monkeypatch) -> list:
    from novelty._kernels import choice

    calls: list = []
    check = choice.check_state
    monkeypatch.setattr(choice, "check_state", lambda det: (calls.append(det), check(det))[1])
    return calls


@pytest.mark.parametrize("reference", [False, True])
def test_a_deep_copy_of_a_checked_state_is_not_checked_again_and_learns_alike(monkeypatch, reference):
    X = corridor(60, n_features=4)
    with reference_loops() if reference else contextlib.nullcontext():
        det = novelty.make("gng-stanley").fit(X[:30])
        det.stream(X[:5])
        calls = _counting_checks(monkeypatch)
        copied = copy.deepcopy(det)
        assert np.array_equal(copied.stream(X[30:]), det.stream(X[30:]))
        assert calls == []  # the original's engine held, the copy's state is its copy
        assert np.array_equal(copied.clusterer_.weights_, det.clusterer_.weights_)


def test_a_deep_copy_torn_by_a_learning_thread_is_refused_not_read(monkeypatch):
    """A copy made while another thread grew the network may hold arrays copied before and
    after the growth, with no change counted on it since: its layout is still checked."""
    X = corridor(60, n_features=4)
    det = novelty.make("gng-stanley").fit(X[:30])
    det.stream(X[:5])
    copied = copy.deepcopy(det)
    efficacy = copied.synapse_.efficacy_
    vars(copied.synapse_)["efficacy_"] = np.concatenate([efficacy, efficacy[:1]])  # torn: uncounted
    with pytest.raises(StateError, match=r"synapse_\.efficacy_ has shape"):
        copied.stream(X[30:32])
    with pytest.raises(StateError, match=r"synapse_\.efficacy_ has shape"):
        copied.score_samples(X[30:32])


@pytest.mark.parametrize("change", ["a part's attribute", "a nested part's", "n_features_in_", "the engine"])
def test_a_deep_copy_changed_before_its_first_call_is_checked(monkeypatch, change):
    X = corridor(60, n_features=4)
    det = novelty.HabituatingFilter(clusterer="gwr", synapse="stanley").fit(X[:30])  # GWR: a nested part
    det.stream(X[:5])
    calls = _counting_checks(monkeypatch)
    copied = copy.deepcopy(det)
    if change == "a part's attribute":
        with damaging(copied):
            copied.clusterer_.weights_ = np.zeros((copied.clusterer_.n_units_, 9))
        error = "clusterer_.weights_ has shape"
    elif change == "a nested part's":
        with damaging(copied):
            copied.clusterer_.firing_.efficacy_ = copied.clusterer_.firing_.efficacy_[:-1]
        error = "firing_.efficacy_ has shape"
    elif change == "n_features_in_":
        vars(copied)["n_features_in_"] = 9
        error = "n_features_in_"
    else:  # the copy's parts given to another filter
        other = copy.deepcopy(det)
        other.clusterer_, other.synapse_ = copied.clusterer_, copied.synapse_
        copied, error = other, None
    scans = np.full((2, 9), 0.5) if change == "n_features_in_" else X[30:32]
    if error is None:
        copied.stream(scans)
    else:
        with pytest.raises(StateError, match=error):
            copied.stream(scans)
    assert len(calls) == 1


@pytest.mark.parametrize("reference", [False, True])
def test_calibrating_keeps_the_engine_and_learns_as_a_new_engine_would(reference):
    # GWR's "auto" radius calibrates one scan at a time: the engine takes the fitted threshold
    # it sets in place, and learns what engines chosen anew after each scan learned
    X = corridor(260)
    with reference_loops() if reference else contextlib.nullcontext():
        kept = novelty.make("gwr-novelty").fit(X[:2])
        engine = kept._current_engine()
        kept_novelty = kept.partial_fit(X[2:]).stream(X[:20])
        assert kept._current_engine() is engine and kept._calibration.full
        anew = novelty.make("gwr-novelty").fit(X[:2])
        built = []
        with pytest.MonkeyPatch.context() as mp:  # every calibrating scan seen as a change
            mp.setattr(type(engine), "take_parameters", lambda self: built.append(1) or False)
            anew_novelty = anew.partial_fit(X[2:]).stream(X[:20])
        assert len(built) > 100
        np.testing.assert_array_equal(kept_novelty, anew_novelty)
        assert kept.clusterer_.activity_threshold_ == anew.clusterer_.activity_threshold_
        np.testing.assert_array_equal(kept.clusterer_.weights_, anew.clusterer_.weights_)


def test_a_calibrate_that_sets_more_than_fitted_parameters_has_the_state_checked():
    det = novelty.make("gwr-novelty").fit(corridor(5))
    engine = det._current_engine()
    clusterer = det.clusterer_
    # set in its __dict__: an attribute set as usual would count as a change of its own
    vars(clusterer)["calibrate"] = lambda scale: setattr(clusterer, "weights_", np.zeros((2, 99)))
    assert engine.holds()
    engine.calibrate(0.5)
    assert not engine.holds()
    with pytest.raises(StateError, match=r"weights_ has shape \(2, 99\)"):
        det.stream(corridor(3))


def test_a_calibrated_threshold_that_is_not_a_finite_number_is_not_taken_in_place():
    det = novelty.make("gwr-novelty").fit(corridor(5))
    engine = det._current_engine()
    clusterer = det.clusterer_
    vars(clusterer)["calibrate"] = lambda scale: setattr(clusterer, "activity_threshold_", float("nan"))
    assert engine.holds()
    engine.calibrate(0.5)
    assert not engine.holds()  # the next call chooses another engine, after the full check


def test_a_calibrate_that_sets_a_nested_part_has_the_state_checked():
    det = novelty.make("gwr-novelty").fit(corridor(5))
    engine = det._current_engine()
    firing = det.clusterer_.firing_
    vars(det.clusterer_)["calibrate"] = lambda scale: setattr(firing, "efficacy_", firing.efficacy_[:1].copy())
    assert engine.holds()
    engine.calibrate(0.5)
    assert not engine.holds()
    with pytest.raises(StateError, match="efficacy_ has shape"):
        det.stream(corridor(3))


# --------------------------------------------------------------- check_values
def _exact_verdict(engine) -> str | None:
    """What the exact checks say of the engine's state: the message, or None."""
    from novelty._kernels.state import check_finite

    try:
        check_finite(engine.state_arrays())
        _exact_norm(engine.clusterer)
        _exact_efficacies(engine.parts)
    except StateError as exc:
        return str(exc)
    return None


def _exact_norm(clusterer) -> None:
    """``Clusterer._check_norm`` without its fast path: the largest row norm, compared."""
    from novelty._validation import MAX_SCAN_NORM
    from novelty.clusterers.base import _largest_norm

    if _largest_norm(clusterer.weights_) > MAX_SCAN_NORM * (1 + 1e-9):
        raise StateError("beyond the bound")


def _exact_efficacies(parts) -> None:
    """Every synapse's efficacy within the scans' norm bound in magnitude, value by value."""
    from novelty._validation import MAX_SCAN_NORM

    for part in parts:
        if part._kind == "synapse" and any(abs(float(e)) > MAX_SCAN_NORM for e in part.efficacy_):
            raise StateError("an efficacy beyond the bound")


def _write(det, where: str, value: float, every: bool) -> None:
    """Write ``value`` in place into the fitted part's ``where``: into one value, or into every
    value (the weights halved: each row within 2x the value, their sum beyond it)."""
    array = getattr(det.clusterer_ if where == "weights_" else det.synapse_, where)
    with damaging(det):
        if every:
            array[...] = value / (2.0 if where == "weights_" else 1.0)
        else:
            array.flat[3] = value


_WRITTEN = [np.nan, np.inf, -np.inf, 1e300, 1e155, 1e150, 1.0000001e100, 1e100, 9.9e99, 1e99, -1e99, 0.5]


@pytest.mark.parametrize("reference", [False, True])
@pytest.mark.parametrize("where", ["weights_", "efficacy_"])
@pytest.mark.parametrize("value", _WRITTEN)
def test_check_values_refuses_exactly_what_the_exact_checks_refuse(reference, where, value):
    """The one-sum-an-array fast path of check_values must not change a verdict: a value
    written in place (one unit, or every unit, each within the bound but their sum beyond
    it) is refused iff the exact checks (every value finite, each row's norm within the
    bound) refuse it."""
    with reference_loops() if reference else contextlib.nullcontext():
        for every in (False, True):
            det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
            det.stream(corridor(5, n_features=4, seed=1))
            engine = det._current_engine()
            _write(det, where, value, every)
            expected = _exact_verdict(engine)
            if expected is None:
                engine.check_values()
            else:
                with pytest.raises(StateError):
                    engine.check_values()


@pytest.mark.parametrize("call", ["score_learn_one", "score_one"])
@pytest.mark.parametrize("where", ["weights_", "efficacy_"])
@pytest.mark.parametrize("value", _WRITTEN)
def test_single_scan_calls_refuse_exactly_what_the_exact_checks_refuse(call, where, value):
    """The compiled single-scan calls check the weights by the scan's distances to them
    (``units_cleared``), not value by value: a value written in place is refused iff the
    exact checks refuse it, and a state they accept gives the reference engine's novelty, bit
    for bit (also for units within the bound whose distances fail the cheap check, which the
    general path takes), or its refusal of a novelty outside the range the synapse keeps."""
    x = corridor(8, n_features=4, seed=2)[5].copy()
    for every in (False, True):
        det = novelty.make("hsom", n_rows=3, n_columns=3).fit(corridor(30, n_features=4))
        assert _kernels.wait(det.clusterer_, det.synapse_) is not None and _kernels.wait() is not None
        det.stream(corridor(5, n_features=4, seed=1))
        det.score_learn_one(x)  # the engine confirmed: the next call takes the compiled path
        engine = det._current_engine()
        assert type(engine) is CompiledEngine and engine.fresh()
        _write(det, where, value, every)
        expected = _exact_verdict(engine)
        if expected is not None:
            with pytest.raises(StateError):
                getattr(det, call)(x)
            continue
        with reference_loops():
            twin = copy.deepcopy(det)
            try:
                want = getattr(twin, call)(x)
            except StateError as refused:
                assert "outside the" in str(refused) and where == "efficacy_"
                with pytest.raises(StateError, match="outside the"):
                    getattr(det, call)(x)
                continue
        got = getattr(det, call)(x)
        assert got == want or (np.isnan(got) and np.isnan(want))


def test_check_values_reads_the_arrays_the_parts_hold_after_the_engine_grew():
    """The arrays check_values sums are listed again when a part was set (the compiled engine
    gives the parts views of new, larger arrays when the network grows): NaN written into the
    grown weights is refused."""
    X = corridor(200, n_features=4)
    det = novelty.make("gng-stanley").fit(X[:2])
    det.stream(X[:3])
    engine = det._current_engine()
    engine.check_values()
    units = det.clusterer_.n_units_
    det.stream(X[3:])  # grows, past the room the engine had
    assert det.clusterer_.n_units_ > units and det._current_engine() is engine
    with damaging(det):
        det.clusterer_.weights_[-1, 0] = np.nan
    with pytest.raises(StateError, match="NaN or infinity"):
        det.stream(X[:2])
