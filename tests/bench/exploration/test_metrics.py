"""Exploration metrics against hand-computed values."""

import json
import math

import numpy as np
import pytest

import novelty
from novelty.bench.exploration.prequential import exploration_metrics, prequential
from novelty.bench.exploration import metrics as xm
from novelty.tasks.exploration import open_door

# run 0 warm-up; runs 1-3 each: 2 familiar scans, 1 scan of the door "d" (exposures 0, 1, 2);
# run 2 also meets a box "b" for the first time
NOVELTY = np.array([1.0, 0.8, 0.2, 0.2, 0.9, 0.1, 0.3, 0.5, 0.7, 0.2, 0.2, 0.3])
RUN = np.array([0, 0, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3])
FEATURE = np.array(["", "", "", "", "d", "", "", "d", "b", "", "", "d"])
EXPOSURE = np.array([-1, -1, -1, -1, 0, -1, -1, 1, 0, -1, -1, 2])


def test_exposure_curves_by_hand():
    curves = xm.exposure_curves(NOVELTY, RUN, FEATURE, EXPOSURE, warmup=1)
    assert sorted(curves) == ["b", "d"]
    d = curves["d"]
    np.testing.assert_allclose(d["novelty"], [0.9, 0.5, 0.3])
    np.testing.assert_allclose(d["familiar"], [0.2, 0.2, 0.2])
    np.testing.assert_allclose(d["excess"], [0.7, 0.3, 0.1])
    assert d["run"].tolist() == [1, 2, 3] and d["exposure"].tolist() == [1, 2, 3]
    np.testing.assert_allclose(curves["b"]["excess"], [0.5])


def test_first_encounter_auc_by_hand():
    # positives 0.9 (d, run 1) and 0.7 (b, run 2); negatives the familiar scans of runs 1-2:
    # 0.2, 0.2, 0.1, 0.3: every positive above every negative
    assert xm.first_encounter_auc(NOVELTY, RUN, FEATURE, EXPOSURE, 1) == 1.0
    low = NOVELTY.copy()
    low[8] = 0.2  # b ties two negatives and beats one, loses to 0.3: (1 + 0.5 * 2) / 4
    assert xm.first_encounter_auc(low, RUN, FEATURE, EXPOSURE, 1) == pytest.approx((4 + 2) / 8)


def test_habituation_by_hand():
    curves = xm.exposure_curves(NOVELTY, RUN, FEATURE, EXPOSURE, warmup=1)
    assert xm.excess_at(curves, 1) == pytest.approx(0.7)   # only d recurs three times
    assert xm.excess_at(curves, 3) == pytest.approx(0.1)
    assert xm.habituation_ratio(curves) == pytest.approx(0.1 / 0.7)
    assert xm.exposures_to_habituate(curves["d"]["excess"]) == 3.0
    assert xm.exposures_to_habituate(curves["d"]["excess"], tolerance=0.5) == 2.0
    assert math.isnan(xm.exposures_to_habituate([-0.1, -0.2]))  # never flagged, never habituated


def test_false_alarms_and_threshold_from_the_last_warmup_run():
    threshold = xm.warmup_threshold(NOVELTY, RUN, 1)
    assert threshold == 1.0
    assert xm.warmup_threshold(NOVELTY, RUN, 1, rule=0.5) == pytest.approx(0.9)
    rate, count = xm.false_alarm_rate(NOVELTY, RUN, FEATURE, 1, 0.25)
    assert (rate, count) == (1 / 6, 1)


def test_redetection_by_hand():
    feature = FEATURE.astype("U2")
    feature[11] = "d2"  # in run 3 the door changes again
    exposure = EXPOSURE.copy()
    exposure[11] = 0
    assert xm.redetection_auc(NOVELTY, RUN, feature, exposure, {"d2": "d"}) == 1.0
    assert math.isnan(xm.redetection_auc(NOVELTY, RUN, FEATURE, EXPOSURE, {"d2": "d"}))


def test_integrated_per_run_is_the_papers_measure():
    np.testing.assert_allclose(xm.integrated_per_run(NOVELTY, RUN, resting=0.1),
                               [1.6, 1.0, 1.2, 0.4])


def test_the_row_of_a_cell():
    row = exploration_metrics(NOVELTY, RUN, FEATURE, EXPOSURE, 1, {}, resting=0.1)
    assert row["first_encounter_auc"] == row["roc_auc"] == 1.0
    assert row["n_first"] == 2 and row["n_recurring"] == 1
    assert row["flags_first"] and row["habituates"]
    assert row["exposures_to_habituate"] == 3.0 and row["habituated_fraction"] == 1.0
    assert json.loads(row["integrated_per_run"]) == pytest.approx([1.6, 1.0, 1.2, 0.4])
    assert json.loads(row["exposure_curve"]) == pytest.approx([0.7, 0.3, 0.1])
    assert row["integrated_novelty"] == pytest.approx(2.6)
    assert row["max_novelty"] == 0.9 and row["false_alarms"] == 0


def test_mismatched_lengths_are_refused():
    with pytest.raises(ValueError, match="one value a scan"):
        xm.exposure_curves(NOVELTY, RUN[:-1], FEATURE, EXPOSURE, 1)


def test_a_network_at_its_synapses_floor_no_longer_flags_nor_habituates():
    # A GWR of a few wide units (Scott's scale, radius 8): every scan but those that add a unit
    # sits at the synapses' floor, so AUC and ratio pass on differences in the fourth decimal.
    task = open_door(0, cycles=3)
    labels = (task.run, task.columns["feature"], task.columns["exposure"], 3, {})
    gamed, det = prequential(lambda: novelty.make("gwr-explore", match_scale="scott", insertion_radius=8.0),
                             task.X, task.run, 3)
    row = exploration_metrics(gamed, *labels)
    assert det.clusterer_.n_units_ <= 8
    assert row["flags_first_auc_only"] and row["habituates_ratio_only"]
    assert row["first_separation"] < 0.1
    assert not row["flags_first"] and not row["habituates"]
    honest, _ = prequential(lambda: novelty.make("gwr-explore-wang-hsu"), task.X, task.run, 3)
    assert exploration_metrics(honest, *labels)["first_separation"] > 10


def test_first_exposure_separation_does_not_depend_on_the_scale():
    rng = np.random.default_rng(0)
    nov, run = rng.random(40), np.repeat([0, 1], 20)
    feature = np.where(np.arange(40) % 5 == 0, "d", "")
    exposure = np.where(feature == "d", 0, -1)
    nov[feature == "d"] += 0.5
    one = xm.first_exposure_separation(nov, run, feature, exposure, 1)
    assert one == pytest.approx(xm.first_exposure_separation(3.0 * nov - 7.0, run, feature, exposure, 1))
    assert one == pytest.approx(xm.first_exposure_separation(1e-120 * nov, run, feature, exposure, 1))
    # familiar scans that do not spread: the spread is a millionth of the novelty's range, 0.1
    flat = np.where(feature == "d", 0.2, 0.1)
    assert xm.first_exposure_separation(flat, run, feature, exposure, 1) == pytest.approx(1e6)
    assert xm.first_exposure_separation(np.full(40, 0.1), run, feature, exposure, 1) == 0.0


def test_first_exposure_separation_ignores_differences_below_the_detectors_resolution():
    """Scans ranked by differences of 1e-84 against a spread of 1e-151, in a detector whose novelty
    spans 3e-35 (first runs) to 0: the ranks are perfect, the separation is nil."""
    rng = np.random.default_rng(1)
    run = np.repeat([0, 1, 2], 20)
    feature = np.where((run > 0) & (np.arange(60) % 5 == 0), "d", "")
    exposure = np.where(feature == "d", 0, -1)
    nov = np.where(feature == "d", 1e-84, 1e-151 * rng.random(60))
    nov[run == 0] = np.linspace(3e-35, 0.0, 20)  # the warm-up: the detector's own range
    assert xm.first_encounter_auc(nov, run, feature, exposure, 1) == 1.0
    separation = xm.first_exposure_separation(nov, run, feature, exposure, 1)
    assert 0 < separation < 1e-40  # 1e-84 over a millionth of 3e-35
    assert separation == pytest.approx((1e-84 - np.median(nov[(run > 0) & (feature == "")])) / 3e-41)


def with_third_door(novelty: float) -> np.ndarray:
    """NOVELTY with the door's 3rd exposure (run 3, familiar level 0.2) scored ``novelty``."""
    out = NOVELTY.copy()
    out[11] = novelty
    return out


@pytest.mark.parametrize("third, ratio, habituates, to_habituate", [
    (0.3, 0.1 / 0.7, True, 3.0),        # excess 0.1: down to a seventh of 0.7
    (0.15, -0.05 / 0.7, True, 3.0),     # a little below the familiar level: as familiar as they are
    (-0.4, -0.6 / 0.7, False, np.nan),  # far below it: told apart from the familiar scans still
])
def test_a_feature_habituates_when_its_excess_falls_to_the_familiar_level_from_either_side(
        third, ratio, habituates, to_habituate):
    row = exploration_metrics(with_third_door(third), RUN, FEATURE, EXPOSURE, 1, {})
    assert row["habituation_ratio"] == pytest.approx(ratio)
    assert row["habituates"] is row["habituates_ratio_only"] is habituates
    np.testing.assert_equal(row["exposures_to_habituate"], to_habituate)


@pytest.mark.parametrize("third", [0.3, -0.4])
@pytest.mark.parametrize("a, b", [(3.0, -7.0), (1.0, -10.0), (1e-3, -5.0), (1e5, 1e5), (0.5, 0.25)])
def test_the_verdicts_do_not_depend_on_the_detectors_scale_or_sign(third, a, b):
    """``a * novelty + b``, a > 0: (1, -10) makes every score negative, as a log-likelihood's."""
    nov = with_third_door(third)
    base = exploration_metrics(nov, RUN, FEATURE, EXPOSURE, 1, {})
    moved = exploration_metrics(a * nov + b, RUN, FEATURE, EXPOSURE, 1, {})
    if (a, b) == (1.0, -10.0):
        assert (a * nov + b).max() < 0
    for column in ("flags_first", "habituates", "flags_first_auc_only", "habituates_ratio_only"):
        assert moved[column] is base[column], column
    for column in ("habituation_ratio", "first_separation", "first_encounter_auc", "exposures_to_habituate"):
        assert moved[column] == pytest.approx(base[column], rel=1e-9, nan_ok=True), column
    assert moved["novelty_range"] == pytest.approx(a * base["novelty_range"])


def test_no_ratio_to_a_first_excess_below_the_detectors_resolution():
    # the door's 1st exposure 1e-9 above its run's familiar level, on a novelty that spans 0 to 1
    nov = np.array([1.0, 0.0, 0.2, 0.2, 0.2 + 1e-9, 0.1, 0.3, 0.2, 0.7, 0.2, 0.2, 0.2])
    curves = xm.exposure_curves(nov, RUN, FEATURE, EXPOSURE, 1)
    assert xm.excess_at(curves, 1) == pytest.approx(1e-9) and xm.excess_at(curves, 3) == 0.0
    assert xm.habituation_ratio(curves) == 0.0                             # 0 / 1e-9: "habituated"
    assert math.isnan(xm.habituation_ratio(curves, resolution=xm.resolution(nov)))  # 1e-9 <= 1e-6
    row = exploration_metrics(nov, RUN, FEATURE, EXPOSURE, 1, {})
    assert math.isnan(row["habituation_ratio"]) and math.isnan(row["exposures_to_habituate"])
    assert not row["habituates_ratio_only"] and not row["habituates"]
    assert row["novelty_range"] == 1.0
