"""Whether an object's place was seen before it appeared: single beams against a disc and a box, by hand."""

import math

import numpy as np
import pytest

from novelty.io.ros.messages import Sweep
from novelty.tasks.objects.places import grown, looks
from novelty.tasks.objects.shapes import Box, Cylinder, Wall

#: A disc of radius 0.2 at (2, 0), appearing at t = 10: grown by 0.1 m its near edge is at x = 1.7.
DISC = Cylinder("disc", 2.0, 0.0, 0.2, start=10.0)


def beam(rng, angle=0.0, time=0.0, pose=(0.0, 0.0, 0.0)):
    """One beam of range ``rng`` from the robot at ``pose``, ``angle`` rad from its heading."""
    return Sweep(float(time), np.zeros((1, 2)), np.array([angle]), np.array([rng], dtype=float), np.array(pose, float))


@pytest.mark.parametrize("rng, seen", [
    (3.0, True),     # passes through the disc
    (1.75, True),    # ends within 0.1 m of it (x in [1.7, 1.8])
    (1.71, True),    # ends just inside the grown edge
    (1.65, False),   # ends 0.15 m short
    (math.inf, True),  # nothing within the sensor's reach: free space through the disc
    (math.nan, False),  # no return: no information
])
def test_a_beam_along_the_axis_sees_the_place_when_it_reaches_the_grown_footprint(rng, seen):
    assert looks([beam(rng)], [DISC]).tolist() == [int(seen)]


def test_a_beam_beside_the_object_counts_within_the_tolerance_only():
    # aimed past the disc: its closest approach to the centre is 2 sin(a) = 0.25 m, outside the disc (0.2)
    past = beam(5.0, angle=math.asin(0.25 / 2.0))
    assert looks([past], [DISC], tolerance=0.1).tolist() == [1]
    assert looks([past], [DISC], tolerance=0.0).tolist() == [0]
    assert looks([past], [DISC], tolerance=0.04).tolist() == [0]


def test_only_the_part_within_reach_and_the_scans_before_the_object_appears_count():
    assert looks([beam(3.0)], [DISC], within=1.5).tolist() == [0]
    assert looks([beam(3.0)], [DISC], within=1.8).tolist() == [1]
    # the disc appears at t = 10: scans at or after it do not tell whether its place was seen
    assert looks([beam(3.0, time=t) for t in (0.0, 9.0, 10.0, 11.0)], [DISC]).tolist() == [2]


def test_the_robots_pose_places_the_beams_in_the_world():
    # from (2, -3) facing +y (yaw pi/2), a beam straight ahead crosses the disc at (2, 0)
    assert looks([beam(4.0, pose=(2.0, -3.0, math.pi / 2))], [DISC]).tolist() == [1]
    assert looks([beam(4.0, pose=(2.5, -3.0, math.pi / 2))], [DISC]).tolist() == [0]   # 0.5 m to the side


def test_each_object_is_counted_apart():
    box = Box("box", 5.0, 0.0, 1.0, 0.4, start=10.0)   # x in [4.5, 5.5]: grown, from 4.4
    sweeps = [beam(4.45), beam(4.35), beam(1.0)]
    assert looks(sweeps, [DISC, box]).tolist() == [2, 1]


def test_grown_shapes_keep_their_place_and_time():
    wall = Wall("w", 0.0, 0.0, 2.0, 0.0, thickness=0.1, start=3.0)
    g = grown(wall, 0.1)
    assert isinstance(g, Box) and (g.x, g.y, g.start) == (1.0, 0.0, 3.0)
    assert g.length == pytest.approx(2.2) and g.width == pytest.approx(0.3)
    assert grown(DISC, 0.0) == DISC
    with pytest.raises(ValueError, match="tolerance must be a length >= 0"):
        grown(DISC, -0.1)
    with pytest.raises(ValueError, match="within must be a positive length"):
        looks([beam(1.0)], [DISC], within=0.0)
