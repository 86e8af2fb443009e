"""Mounts: a laser's beams seen from above in the base frame, upside down, turned, offset or tilted."""

import math

import numpy as np
import pytest

from novelty.io.frames.mounts import Mount, parse_mount
from novelty.io.frames.tf import Placement

from ...io.scenes import quaternion

ANGLES = np.deg2rad([-90.0, -30.0, 30.0, 90.0])


def test_an_upside_down_laser_sweeps_clockwise():
    origins, directions, scale = Mount.planar(flipped=True).beams(ANGLES)
    np.testing.assert_allclose(directions, -ANGLES, atol=1e-12)
    assert scale == pytest.approx(1.0) and origins.tolist() == [[0.0, 0.0]] * 4


def test_a_turned_offset_laser():
    origins, directions, _ = Mount.planar(0.3, -0.1, math.pi, origin="tf").beams(ANGLES)
    np.testing.assert_allclose(directions, ANGLES + math.pi, atol=1e-12)   # unwrapped: one piece across the back
    assert origins.tolist() == [[0.3, -0.1]] * 4


def test_a_tilted_laser_sees_the_floor_plane_foreshortened_and_a_steep_one_is_refused():
    tilted = Mount(Placement((0, 0, 0), quaternion(pitch=math.radians(20))))
    _, directions, scale = tilted.beams(np.array([0.0, math.pi / 2]))
    assert scale == pytest.approx([math.cos(math.radians(20)), 1.0])
    with pytest.raises(ValueError, match="leave the floor plane by up to 45 degrees"):
        Mount(Placement((0, 0, 0), quaternion(roll=math.radians(45)))).beams(ANGLES)


@pytest.mark.parametrize("text, topic, described", [
    ("0.2,0,90", None, "x=0.2 m, y=0 m, yaw=90 deg, from option"),
    ("/rear=-0.3,0.1,-180,flipped", "/rear", "x=-0.3 m, y=0.1 m, yaw=-180 deg, upside down, from option"),
])
def test_mount_options(text, topic, described):
    got_topic, mount = parse_mount(text)
    assert got_topic == topic and mount.describe() == described


@pytest.mark.parametrize("text", ["0.2,0", "a,b,c", "0,0,nan", "/scan=1,2,3,sideways"])
def test_bad_mount_options(text):
    with pytest.raises(ValueError, match=r"mount|finite"):
        parse_mount(text)


def test_centred():
    assert Mount().centred and not Mount.planar(0.1).centred and not Mount.planar(flipped=True).centred
