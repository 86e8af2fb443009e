"""The Bayesian signed-rank test (Benavoli et al. 2017) on cases whose answer is known."""

import numpy as np
import pytest

from novelty.bench.stats.bayesian import bayesian_signed_rank


def test_every_difference_inside_the_rope_is_equivalence():
    r = bayesian_signed_rank([0.800, 0.700, 0.905, 0.61], [0.801, 0.709, 0.9, 0.61])
    assert (r.left, r.equivalent, r.right) == (0.0, 1.0, 0.0)
    assert r.decision() == "equivalent"


def test_many_clear_wins_are_better_and_losses_worse():
    a, b = np.linspace(0.8, 0.9, 15), np.linspace(0.7, 0.8, 15)
    assert bayesian_signed_rank(a, b).right == 1.0
    assert bayesian_signed_rank(b, a).left == 1.0
    assert bayesian_signed_rank(a, b).decision() == "better"


def test_two_wins_rest_on_the_prior_by_its_closed_form():
    # z = (0, +d, +d): theta_right = 1 - w0^2 and theta_rope = w0^2 with w0 ~ Beta(0.5, 2);
    # right wins when w0 < 1/sqrt(2): P = I_{1/sqrt 2}(0.5, 2)
    from scipy.stats import beta

    r = bayesian_signed_rank([0.9, 0.9], [0.8, 0.8], samples=50_000)
    assert r.right == pytest.approx(beta.cdf(2 ** -0.5, 0.5, 2), abs=0.005)
    assert r.left == 0.0 and r.right + r.equivalent == pytest.approx(1.0)


def test_probabilities_sum_to_one_are_seeded_and_skip_missing_tasks():
    a, b = [0.9, 0.6, 0.8, 0.7, np.nan], [0.8, 0.7, 0.7, 0.8, 0.5]
    r = bayesian_signed_rank(a, b)
    assert r.n == 4 and r.left + r.equivalent + r.right == pytest.approx(1.0)
    assert r == bayesian_signed_rank(a, b)


def test_a_negative_rope_is_refused():
    with pytest.raises(ValueError, match="rope must be >= 0"):
        bayesian_signed_rank([0.5], [0.4], rope=-0.1)
