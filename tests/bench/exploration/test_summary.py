"""The exploration table: which detectors flag first encounters and habituate."""

import math

import pytest

from novelty.bench.exploration.summary import exploration_markdown, exploration_records, exploration_text


def row(detector, seed, auc, e1, e3, **extra):
    return {"status": "ok", "detector": detector, "task": "t", "seed": seed, "cell_id": f"{detector}{seed}",
            "policy": "online", "first_encounter_auc": auc, "excess_1": e1, "excess_2": (e1 + e3) / 2,
            "excess_3": e3, "exposures_to_habituate": 3.0, "habituated_fraction": 1.0,
            "false_alarm_rate": 0.0, "redetection_auc": None, "first_separation": 2.0, **extra}


ROWS = [row("both", 0, 0.9, 0.4, 0.05), row("both", 1, 0.9, 0.2, 0.05),        # ratio 0.05/0.3
        row("flat", 0, 0.95, 0.4, 0.4), row("blind", 0, 0.5, 0.01, 0.0),
        # AUC and ratio pass, ranked by differences far below the familiar spread: neither counts
        row("gamed", 0, 0.9, 0.1, 0.001, first_separation=0.1),
        row("gamed", 1, 0.9, 0.1, 0.001, first_separation=float("inf")),
        row("gamed", 2, 0.9, 0.1, 0.001, first_separation=0.2),
        {"status": "ok", "detector": "holdout", "task": "t", "seed": 0, "cell_id": "h"}]


def test_records_say_who_flags_and_who_habituates():
    records = {r["detector"]: r for r in exploration_records(ROWS)["t"]}
    assert set(records) == {"both", "flat", "blind", "gamed"}   # hold-out rows have no policy
    assert records["both"]["ratio"] == pytest.approx(0.05 / 0.3) and records["both"]["auc_sd"] == 0.0
    assert (records["both"]["flags"], records["both"]["habituates"], records["both"]["both"]) == (True, True, True)
    assert (records["flat"]["flags"], records["flat"]["habituates"]) == (True, False)
    assert (records["blind"]["flags"], records["blind"]["habituates"]) == (False, True)
    gamed = records["gamed"]
    assert gamed["separation"] == 0.2     # the median over seeds
    assert (gamed["flags"], gamed["habituates"], gamed["flags_auc_only"], gamed["habituates_ratio_only"]) == \
        (False, False, True, True)
    assert [r["detector"] for r in exploration_records(ROWS)["t"]] == ["both", "flat", "gamed", "blind"]


def test_text_and_markdown():
    text = exploration_text(ROWS)
    assert text.startswith("### t (seeds 0, 1, 2)") and "| both " in text and "| separation |" in text
    assert exploration_markdown([ROWS[-1]]) == []
    assert "## Exploration: first encounters and habituation" in exploration_markdown(ROWS)


def test_a_third_excess_far_below_the_familiar_level_does_not_habituate():
    """lof (window=3) on a real robot's log: 1st excess 0.233, 3rd -0.213: a ratio of -0.91."""
    records = {r["detector"]: r for r in exploration_records(
        [row("below", 0, 0.7, 0.233, -0.213), row("near", 0, 0.7, 0.233, -0.05)])["t"]}
    assert records["below"]["ratio"] == pytest.approx(-0.213 / 0.233)
    assert not records["below"]["habituates"] and not records["below"]["habituates_ratio_only"]
    assert records["near"]["habituates"]


def test_no_ratio_when_the_first_excess_is_below_the_detectors_resolution():
    # mean range 3.0 over the seeds: resolution 3e-6; a mean 1st excess of 2e-6 is none
    rows = [row("faint", 0, 0.9, 1e-6, 0.0, novelty_range=2.0), row("faint", 1, 0.9, 3e-6, 0.0, novelty_range=4.0),
            row("clear", 0, 0.9, 4e-6, 0.0, novelty_range=2.0), row("clear", 1, 0.9, 4e-6, 0.0, novelty_range=4.0)]
    records = {r["detector"]: r for r in exploration_records(rows)["t"]}
    assert math.isnan(records["faint"]["ratio"]) and not records["faint"]["habituates"]
    assert records["clear"]["ratio"] == 0.0 and records["clear"]["habituates"]
    # rows recorded before the range was: the ratio as before
    assert exploration_records([row("old", 0, 0.9, 1e-6, 0.0)])["t"][0]["ratio"] == 0.0
