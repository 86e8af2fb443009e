import numpy as np
import pytest

from novelty.sonar import RunVariation, get_environment
from novelty.sonar.pursuit import WaypointFollower


def test_waypoint_follower_tracks_its_course():
    env = get_environment("control")
    traj = env.controller.drive(env.world, env.start, 10.0, RunVariation().none(),
                                np.random.default_rng(0))
    assert traj.poses[:, 1].max() > 2.5  # reached the middle of the hall
    assert traj.poses[-1, 1] == pytest.approx(0.55, abs=0.1)  # and came back to the wall
    assert isinstance(env.controller, WaypointFollower)
