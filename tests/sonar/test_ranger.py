"""The Polaroid ranger, answers known: the beam, echoes from simple walls, readings in inches."""

import math

import numpy as np
import pytest

from novelty.sonar import NOMAD_200, PolaroidRanger
from novelty.sonar.materials import MATERIALS
from novelty.sonar.ranger import INCH
from novelty.sonar.world import MapBuilder

QUIET = PolaroidRanger(noise_sd=0.0, noise_fraction=0.0, dropout=0.0)
RIGHT = 12  # sensor 12 points 270 degrees from ahead: to the right


def _wall_map(material, p0=(-20, 0), p1=(20, 0), z=(0.0, 2.6)):
    b = MapBuilder()
    b.wall(p0, p1, material, z=z)
    return b.build()


def test_beam_half_angle_is_the_piston_first_null():
    # sin(theta0) = 0.61 lambda / a (Kuc & Siegel 1987): about 12.7 degrees for the Polaroid
    assert math.degrees(QUIET.beam_half_angle) == pytest.approx(12.74, abs=0.05)
    assert QUIET.gain(0.0) == 1.0
    assert QUIET.gain(QUIET.beam_half_angle + 1e-3) == 0.0


@pytest.mark.parametrize("material", ["breezeblock", "wood", "brick", "glass", "laminate"])
@pytest.mark.parametrize("distance", [0.5, 1.3, 3.0])
def test_sonar_facing_a_wall_reads_its_distance(material, distance):
    world = _wall_map(material)
    pose = [[0.0, distance + NOMAD_200.sonar_ring_radius, 0.0]]  # transducer `distance` from the wall
    echoes = QUIET.cast(world, pose)
    assert echoes.ranges[0, RIGHT] == pytest.approx(distance, abs=1e-9)
    assert echoes.source[0, RIGHT] == 1
    reading = QUIET.read(echoes.ranges, np.random.default_rng(0))
    assert reading[0, RIGHT] == pytest.approx(distance, abs=1e-9)


def test_range_noise_has_the_documented_spread():
    ranger = PolaroidRanger(dropout=0.0)
    readings = ranger.read(np.full(20000, 2.0), np.random.default_rng(1))
    assert readings.mean() == pytest.approx(2.0, abs=0.002)
    assert readings.std() == pytest.approx(0.01 + 0.01 * 2.0, rel=0.05)


def test_no_echo_reads_max_range():
    out = QUIET.read(np.array([np.inf, 1.0]), np.random.default_rng(0))
    assert out.tolist() == [6.5, 1.0]


def _aim(angle_deg, distance=1.0, sensor=0):
    """A pose whose sensor ``sensor`` meets the wall y=0 at ``angle_deg`` incidence, ``distance`` away."""
    a = math.radians(-90 + angle_deg)  # axis direction, pointing down at the wall
    heading = a - NOMAD_200.sonar_angles()[sensor]
    x = -NOMAD_200.sonar_ring_radius * math.cos(a) - distance * math.cos(a)
    y = -NOMAD_200.sonar_ring_radius * math.sin(a) - distance * math.sin(a)
    return [[x, y, heading]]


def test_specular_wall_at_steep_incidence_gives_no_echo_but_a_rough_one_does():
    pose = _aim(30.0)
    glass = QUIET.cast(_wall_map("glass"), pose)
    block = QUIET.cast(_wall_map("breezeblock"), pose)
    assert np.isinf(glass.ranges[0, 0])
    assert glass.source[0, 0] == 0
    # breezeblock is heard to about 40 degrees: its nearest-to-normal ray answers
    assert np.isfinite(block.ranges[0, 0])
    assert block.ranges[0, 0] < 1.0 / math.cos(math.radians(30.0))


def test_max_incidence_matches_the_material_table():
    assert MATERIALS["breezeblock"].max_incidence() == pytest.approx(39.8, abs=0.1)
    assert MATERIALS["glass"].max_incidence() < 6.0
    assert MATERIALS["aperture"].max_incidence() == 0.0


def test_corner_of_two_mirrors_returns_a_multipath_echo_at_the_corner():
    b = MapBuilder()
    b.wall((0.0, 0.0), (5.0, 0.0), "glass")
    b.wall((0.0, 0.0), (0.0, 5.0), "glass")
    world = b.build()
    d = 2.0
    axis = math.radians(225.0)  # pointing into the corner along its bisector
    sx, sy = -d * math.cos(axis), -d * math.sin(axis)
    pose = [[sx - NOMAD_200.sonar_ring_radius * math.cos(axis),
             sy - NOMAD_200.sonar_ring_radius * math.sin(axis), axis]]
    echoes = QUIET.cast(world, pose)
    assert echoes.source[0, 0] == 2
    assert echoes.ranges[0, 0] == pytest.approx(d, abs=0.05)
    single = PolaroidRanger(noise_sd=0.0, noise_fraction=0.0, dropout=0.0, multipath=False)
    assert np.isinf(single.cast(world, pose).ranges[0, 0])


def test_echoes_nearer_than_the_blanking_distance_are_not_heard():
    world = _wall_map("breezeblock")
    pose = [[0.0, 0.1 + NOMAD_200.sonar_ring_radius, 0.0]]
    assert np.isinf(QUIET.cast(world, pose).ranges[0, RIGHT])


def test_low_object_passes_under_the_beam_full_height_one_does_not():
    pose = [[0.0, 1.2 + NOMAD_200.sonar_ring_radius, 0.0]]
    low = QUIET.cast(_wall_map("cardboard", z=(0.0, 0.4)), pose)
    tall = QUIET.cast(_wall_map("cardboard", z=(0.0, 1.0)), pose)
    assert np.isinf(low.ranges[0, RIGHT])
    assert tall.ranges[0, RIGHT] == pytest.approx(1.2)


def test_edge_is_heard_only_within_its_range():
    for distance, heard in [(0.5, True), (1.5, False)]:
        b = MapBuilder()
        b.edge((0.0, 0.0), heard_to=1.0)
        pose = [[0.0, distance + NOMAD_200.sonar_ring_radius, 0.0]]
        r = QUIET.cast(b.build(), pose).ranges[0, RIGHT]
        assert np.isfinite(r) == heard
        if heard:
            assert r == pytest.approx(distance)


def test_edge_behind_a_silent_pane_is_not_heard():
    pose = [[0.0, 0.8 + NOMAD_200.sonar_ring_radius, 0.0]]
    b = MapBuilder()
    b.edge((0.0, 0.0), heard_to=2.0)
    assert QUIET.cast(b.build(), pose).ranges[0, RIGHT] == pytest.approx(0.8)
    # a glass pane across the line of sight, tilted 22 degrees: too steep to echo,
    # but it still blocks the edge behind it
    tilt = math.radians(22.0)
    b.wall((-0.6 * math.cos(tilt), 0.4 - 0.6 * math.sin(tilt)),
           (0.6 * math.cos(tilt), 0.4 + 0.6 * math.sin(tilt)), "glass")
    echoes = PolaroidRanger(noise_sd=0.0, noise_fraction=0.0, dropout=0.0,
                            multipath=False).cast(b.build(), pose)
    assert np.isinf(echoes.ranges[0, RIGHT])


def test_readings_in_whole_inches_are_the_continuous_ones_rounded():
    """The Nomad reports whole inches; ``resolution`` rounds each reading to the nearest."""
    ranges = np.array([0.5, 1.0, 2.345, np.inf])
    continuous = PolaroidRanger().read(ranges, np.random.default_rng(4))
    inches = PolaroidRanger(resolution=INCH).read(ranges, np.random.default_rng(4))
    np.testing.assert_allclose(inches / INCH, np.round(inches / INCH), atol=1e-9)
    assert np.all(np.abs(inches - continuous) <= INCH / 2 + 1e-12)
    assert QUIET.resolution is None


def test_resolution_must_be_positive():
    with pytest.raises(ValueError, match="resolution"):
        PolaroidRanger(resolution=0.0)


def test_without_edge_echoes_an_edge_alone_is_silent():
    b = MapBuilder()
    b.edge((0.0, 0.0), heard_to=1.0)
    pose = [[0.0, 0.5 + NOMAD_200.sonar_ring_radius, 0.0]]
    silent = PolaroidRanger(noise_sd=0.0, noise_fraction=0.0, dropout=0.0, edges=False)
    assert np.isfinite(QUIET.cast(b.build(), pose).ranges[0, RIGHT])
    assert np.isinf(silent.cast(b.build(), pose).ranges[0, RIGHT])
