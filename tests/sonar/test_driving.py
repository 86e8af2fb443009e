import math

import numpy as np
import pytest

from novelty.sonar.driving import RunVariation, _Drive, _step, _wrap


def test_a_step_moves_along_the_new_heading():
    # dyadic values: every coordinate exact
    pose = np.array([1.0, 2.0, 0.0])
    travelled = _step(pose, speed=0.5, turn=0.0, dt=0.25, travelled=3.0)
    assert travelled == 3.125
    assert pose.tolist() == [1.125, 2.0, 0.0]
    pose = np.array([0.0, 0.0, 0.0])
    _step(pose, speed=1.0, turn=math.pi, dt=0.5, travelled=0.0)  # turn first: heading pi/2
    assert pose[2] == pytest.approx(math.pi / 2, abs=1e-15)
    assert pose[0] == pytest.approx(0.0, abs=1e-15) and pose[1] == pytest.approx(0.5, abs=1e-15)


def test_angles_wrap_into_minus_pi_to_pi():
    assert _wrap(0.5) == pytest.approx(0.5, abs=1e-15)
    assert _wrap(math.pi) == pytest.approx(-math.pi, abs=1e-15)
    assert _wrap(2 * math.pi + 0.25) == pytest.approx(0.25, abs=1e-12)


def test_without_variation_every_draw_is_the_nominal_value():
    var = RunVariation(speed=0.25).none()
    draws = _Drive.draw(var, np.random.default_rng(7), 50, 0.1)
    assert np.all(draws.speed == 0.25)
    assert np.all(draws.offset == 0.0) and np.all(draws.jitter == 0.0) and np.all(draws.start == 0.0)


def test_the_same_seed_draws_the_same_run():
    a = _Drive.draw(RunVariation(), np.random.default_rng(3), 40, 0.1)
    b = _Drive.draw(RunVariation(), np.random.default_rng(3), 40, 0.1)
    for name in ("speed", "offset", "jitter", "start"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
