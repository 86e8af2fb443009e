"""A trial of the paper's protocol: its integrated and maximum output, and when a run shows only the resting activity."""

import numpy as np
import pytest

from novelty.reproduce import Trial, is_resting

RESTING = 0.0476


def test_integrated_and_maximum_are_the_papers_measures():
    t = Trial("A", "1", "L", np.array([1.0, 0.5, RESTING]), np.array([0.1, 0.2, 0.3]), RESTING, 0)
    assert t.integrated == pytest.approx(1.0 + 0.5 + RESTING - 3 * RESTING)
    assert t.maximum == 1.0 and t.label == "1 (L)"
    assert is_resting(Trial("A", "6", "NL", np.full(100, RESTING + 0.003), np.arange(100), RESTING, 0))
    one_peak = np.r_[0.42, np.full(99, RESTING)]
    assert not is_resting(Trial("A", "6", "NL", one_peak, np.arange(100), RESTING, 0))
