"""The registry of datasets: every built-in listed with a description, unknown parameters refused."""

import pytest

from novelty import datasets
from novelty.registry import InvalidParameterError

PAPER = ["paper-a", "paper-a-star", "paper-b", "paper-c", "paper-control"]


def test_every_builtin_is_listed_with_a_description():
    names = datasets.available()
    for name in PAPER + ["paper-a-to-a-star", "paper-a-to-b", "paper-a-to-c", "inspection",
                         "inspection-easy", "inspection-medium", "inspection-hard",
                         "uci-wall-following", "uci-wall-following-novelty", "uci-sonar",
                         "uci-sonar-mines"]:
        assert names[name]


def test_unknown_parameter_is_refused_with_the_valid_ones():
    with pytest.raises(InvalidParameterError, match="Valid parameters: run, runs, seed"):
        datasets.load("paper-b", rnu=1)
