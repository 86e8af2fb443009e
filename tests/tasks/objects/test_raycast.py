"""Objects cast into sweeps: a corridor and a box, every beam computed by hand; cones; labels."""

import math

import numpy as np
import pytest

from novelty.tasks.objects.raycast import cone_range, inject, world_beams
from novelty.tasks.objects.shapes import Box, Cylinder
from novelty.io.ros.messages import Sweep
from novelty.io.scans.sweep_rings import sweep_ring

R2 = math.sqrt(2)
ANGLES = np.deg2rad([-90.0, -45.0, 0.0, 45.0, 90.0])


def corridor(pose=(1.0, 0.0, 0.0), origin=(0.0, 0.0), time=0.0, ranges=None):
    """A corridor along x between walls at y = -1 and y = 1, open ahead; the laser at ``origin`` in the base frame."""
    if ranges is None:   # from the laser at y = origin[1] (the robot at y = 0): 1 and sqrt(2) to the walls
        ranges = [1.0, R2, math.inf, R2, 1.0]
    return Sweep(time, np.tile(origin, (5, 1)).astype(float), ANGLES.copy(), np.array(ranges, dtype=float),
                 np.array(pose, dtype=float))


BOX = Box("crate", x=4.5, y=0.0, length=1.0, width=0.5)      # x in [4, 5], y in [-0.25, 0.25]


def test_a_box_in_the_corridor_shortens_the_beam_that_meets_it():
    out = inject(corridor(), [BOX])
    # the beam ahead meets the near face x = 4 from x = 1: 3 m; the others still see the walls
    assert out.sweep.ranges.tolist() == [1.0, R2, 3.0, R2, 1.0]
    assert out.shortened.tolist() == [1] and out.nearest.tolist() == [-1, -1, 0, -1, -1]


def test_the_sensors_mount_and_the_robots_heading_are_used():
    # the laser 0.5 m ahead of the base: the box is 2.5 m from it
    assert inject(corridor(origin=(0.5, 0.0)), [BOX]).sweep.ranges[2] == pytest.approx(2.5)
    # the robot at (4.5, -3) facing +y (yaw 90 degrees): the beam ahead meets the face y = -0.25 at 2.75 m,
    # the beam to its right (-90 degrees, along +x in the world) misses
    facing = corridor(pose=(4.5, -3.0, math.pi / 2), ranges=[math.inf] * 5)
    origins, angles = world_beams(facing)
    assert origins.tolist() == [[4.5, -3.0]] * 5 and angles[2] == pytest.approx(math.pi / 2)
    assert inject(facing, [BOX]).sweep.ranges.tolist() == pytest.approx([math.inf, math.inf, 2.75, math.inf,
                                                                          math.inf])


def test_an_object_behind_a_wall_stays_hidden_and_the_nearer_object_wins():
    behind = Box("behind", x=1.0, y=2.0, length=0.5, width=0.5)      # beyond the wall y = 1, straight left
    front = Cylinder("front", x=2.0, y=0.0, radius=0.2)             # ahead, 0.8 m from the robot
    out = inject(corridor(), [behind, BOX, front])
    assert out.sweep.ranges.tolist() == pytest.approx([1.0, R2, 0.8, R2, 1.0])
    assert out.shortened.tolist() == [0, 0, 1]


def test_beams_of_no_information_take_the_object_and_the_sensor_reach_limits_it():
    out = inject(corridor(ranges=[1.0, R2, math.nan, R2, 1.0]), [BOX])
    assert out.sweep.ranges[2] == 3.0 and out.shortened.tolist() == [1]
    far = inject(corridor(), [BOX], max_range=2.0)
    assert math.isinf(far.sweep.ranges[2]) and far.shortened.tolist() == [0]


def test_labels_count_beams_shortened_by_more_than_the_margin_within_reach():
    # the recorded range ahead is 3.05: the box at 3 m shortens it by 0.05, below the margin
    near_wall = inject(corridor(ranges=[1.0, R2, 3.05, R2, 1.0]), [BOX], margin=0.1)
    assert near_wall.sweep.ranges[2] == 3.0 and near_wall.shortened.tolist() == [0]
    assert inject(corridor(), [BOX], within=2.5).shortened.tolist() == [0]   # 3 m is beyond the ring's 2.5 m


def test_an_absent_object_changes_nothing():
    later = Box("crate", 4.5, 0.0, 1.0, 0.5, start=10.0)
    out = inject(corridor(time=5.0), [later])
    assert out.sweep.ranges.tolist() == [1.0, R2, math.inf, R2, 1.0] and out.shortened.tolist() == [0]


def test_the_new_sweep_keeps_its_geometry_and_makes_the_ring():
    sweep = corridor()
    out = inject(sweep, [BOX]).sweep
    assert out.angles is sweep.angles and out.origins is sweep.origins and out.time == sweep.time
    assert sweep_ring(out, 5).tolist() == [1.0, R2, 3.0, R2, 1.0]


def test_a_cone_sees_the_nearest_point_within_it():
    origin = [[0.0, 0.0]]
    inside = Cylinder("in", x=2.0, y=1.0, radius=0.5)     # its nearest point at 26.6 degrees, within 45
    assert cone_range(inside, origin, [0.0], [0.0])[0] == math.inf
    assert cone_range(inside, origin, [0.0], [math.pi / 2])[0] == pytest.approx(math.sqrt(5) - 0.5)
    # nearest point at 56.3 degrees, beyond the cone: the cone's edge at 45 degrees enters it at (1, 1)
    edge = Cylinder("edge", x=1.0, y=1.5, radius=0.5)
    assert cone_range(edge, origin, [0.0], [math.pi / 2])[0] == pytest.approx(R2)
    # a cone wider than half a turn is cut into convex parts: the same object seen behind-left
    assert cone_range(edge, origin, [math.pi], [1.9 * math.pi])[0] == pytest.approx(math.sqrt(1 + 2.25) - 0.5)


def test_a_sonar_sweep_is_cast_with_its_cones():
    sonar = Sweep(0.0, np.zeros((1, 2)), np.array([0.0]), np.array([5.0]), np.zeros(3), spread=np.array([math.pi / 2]))
    out = inject(sonar, [Cylinder("pole", 2.0, 1.0, 0.5)])
    assert out.sweep.ranges[0] == pytest.approx(math.sqrt(5) - 0.5)


def test_a_sweep_without_a_pose_is_refused():
    sweep = Sweep(0.0, np.zeros((5, 2)), ANGLES, np.ones(5), None)
    with pytest.raises(ValueError, match="has no pose"):
        inject(sweep, [BOX])


@pytest.mark.parametrize("option", [dict(margin=-0.1), dict(within=float("nan")), dict(max_range=-1.0)])
def test_bad_options_are_refused(option):
    with pytest.raises(ValueError, match="must be a length"):
        inject(corridor(), [BOX], **option)
