"""A neighbour learning rate of its own (not in the paper) lets the simulated A settle faster."""

import pytest

from novelty.reproduce.experiments import sensitivity
from novelty.reproduce.experiments._common import PAPER_A, six_trials


@pytest.mark.parametrize("seed", (0, 1))
def test_a_smaller_neighbour_rate_settles_faster_than_the_papers_on_simulated_a(seed):
    paper = six_trials(seed)
    own = six_trials(seed, {"neighbour_learning_rate": 0.05})
    assert own["integrated"][5] < 0.5 * paper["integrated"][5]
    assert sum(own["integrated"][1::2]) < 0.5 * sum(paper["integrated"][1::2])
    assert own["learning_winners"] < paper["learning_winners"]


def test_fold_is_the_largest_factor_either_way():
    assert sensitivity.fold(PAPER_A) == 1.0
    assert sensitivity.fold([v * 2 for v in PAPER_A[:5]] + [PAPER_A[5] / 3]) == pytest.approx(3.0)
