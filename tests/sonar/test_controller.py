import numpy as np
import pytest

from novelty.sonar import RunVariation, WallFollower, get_environment
from novelty.sonar.environments import corridor_environment


def _plain():
    return corridor_environment("plain", 1.7, "breezeblock", "breezeblock")


def test_without_variation_the_follower_runs_straight_at_the_set_distance():
    env = _plain()
    traj = WallFollower().drive(env.world, env.start, 10.0, RunVariation().none(),
                                np.random.default_rng(0))
    assert traj.odometry[-1] == pytest.approx(10.0, abs=0.03)
    assert np.abs(traj.poses[:, 1] - 0.55).max() < 1e-9
    assert np.abs(traj.poses[:, 2]).max() < 1e-12


def test_with_variation_it_stays_near_the_wall_and_runs_differ():
    env = _plain()
    ys = []
    for run in range(4):
        traj = WallFollower().drive(env.world, env.start, 10.0, RunVariation(),
                                    np.random.default_rng(run))
        ys.append(traj.poses[:, 1])
        assert 0.4 < traj.poses[:, 1].min() and traj.poses[:, 1].max() < 0.72
    assert len({round(float(y.mean()), 4) for y in ys}) == 4


def test_follower_recovers_from_a_start_off_the_set_distance():
    env = _plain()
    traj = WallFollower().drive(env.world, (0.0, 0.8, 0.0), 10.0, RunVariation().none(),
                                np.random.default_rng(0))
    assert abs(traj.poses[-1, 1] - 0.55) < 0.02


def test_follower_holds_course_past_an_open_door():
    env = get_environment("a-star")
    traj = env.controller.drive(env.world, env.start, 10.0, RunVariation().none(),
                                np.random.default_rng(0))
    assert traj.poses[:, 1].min() > 0.35  # never turns into the doorway
