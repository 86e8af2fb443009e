"""Table 1's maxima against the efficacies each integration of the synapse can reach."""

import math

import pytest

from novelty.reproduce.experiments import maxima


def test_winner_steps_give_the_closed_forms():
    y_inf = 1 - 1 / 1.05
    euler, exact = maxima.efficacies("euler", 3, 2), maxima.efficacies("exact", 3, 2)
    for w in range(4):
        for n in range(3):
            assert euler[w, n] == pytest.approx(y_inf + (1 - y_inf) * (1 - 1.05 / 3.33) ** w
                                                * (1 - 1.05 / 14.3) ** n, rel=1e-12)
            assert exact[w, n] == pytest.approx(y_inf + (1 - y_inf) * math.exp(-1.05 * (w / 3.33 + n / 14.3)),
                                                rel=1e-12)
    assert round(euler[3, 0], 4) == 0.3533 and round(exact[3, 0], 4) == 0.4174


def test_042_is_three_exact_winner_steps_and_no_unit_euler_steps():
    assert maxima.fits(0.42, maxima.efficacies("exact"))[0] == (3, 0)
    assert maxima.fits(0.42, maxima.efficacies("euler")) == []


def test_065_is_a_euler_winner_step_then_a_neighbour_step():
    assert maxima.fits(0.65, maxima.efficacies("euler"))[0] == (1, 1)
