"""A's six trials as the experiments run them are the protocol's, and winners are counted exactly."""

import io

import numpy as np

import novelty
from novelty.reproduce.experiments._common import (learn_counting_winners, markdown_table, parallel, reporting,
                                                   six_trials, traversal)


def test_six_trials_are_the_protocols_a_column_for_seed_0():
    """The guide's Table 1 for seed 0: 27.02, 22.66, 14.46, 14.37, 10.41, 10.84."""
    found = six_trials(0)
    assert [round(v, 2) for v in found["integrated"]] == [27.02, 22.66, 14.46, 14.37, 10.41, 10.84]
    assert found["learning_winners"] >= max(found["distinct"][0::2])
    assert 0.0 <= found["rare_share"] <= 1.0


def test_counting_winners_learns_exactly_as_stream_does():
    X = traversal("a", 0, 0)
    counted, reference = novelty.make("hsom", random_state=0), novelty.make("hsom", random_state=0)
    novelty_, winners = learn_counting_winners(counted, X)
    np.testing.assert_array_equal(novelty_, reference.stream(X))
    np.testing.assert_array_equal(counted.clusterer_.weights_, reference.clusterer_.weights_)
    # the first two scans are nearly alike: the same winner, after one winner step (0.6997)
    assert winners[0] == winners[1] and round(novelty_[1], 4) == 0.6997


def test_markdown_table_right_aligns_numbers():
    text = markdown_table([{"name": "a", "value": 1.234}])
    assert text.splitlines() == ["| name | value |", "| --- | ---: |", "| a | 1.23 |"]


def test_steps_of_an_experiment_are_reported_while_reporting_and_only_then(capsys):
    stream = io.StringIO()
    with reporting("ablations", stream):
        assert parallel(abs, [-1, -2, -3], jobs=1) == [1, 2, 3]
    lines = stream.getvalue().splitlines()
    assert [line.split(" (")[0] for line in lines] == [f"ablations: step {k} of 3" for k in (1, 2, 3)]
    assert parallel(abs, [-1, -2], jobs=1) == [1, 2]  # outside: silent
    assert stream.getvalue().splitlines() == lines and capsys.readouterr() == ("", "")
