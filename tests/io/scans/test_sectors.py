"""Invalid readings, laser sectors and sonar rings, against values worked out by hand."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from novelty.io.ros.messages import LaserScan, RangeReading
from novelty.io.scans.sectors import all_round, reduce_sectors, sector_index
from novelty.io.scans.ranges import clean_ranges
from novelty.io.scans.sweep_rings import laser_ring
from novelty.io.scans.sonar_rings import sonar_rings
from novelty.sonar.preprocessing import preprocess

INF, NAN = math.inf, math.nan


def test_clean_ranges_follows_rep_117():
    # +inf: nothing within range (kept); -inf: too close (range_min); NaN and out of range: no information
    out = clean_ranges([0.5, INF, -INF, NAN, 0.05, 12.0, 0.1, 10.0], range_min=0.1, range_max=10.0)
    np.testing.assert_array_equal(out, [0.5, INF, 0.1, NAN, NAN, NAN, 0.1, 10.0])


def test_sixteen_sectors_of_a_180_beam_laser():
    # 180 beams 1 degree apart from -89.5 to 89.5: the span -90..90 in sixteen 11.25-degree sectors
    angles = np.deg2rad(np.arange(180) - 89.5)
    k = sector_index(angles, 16)
    expected = np.floor((np.arange(180) + 0.5) / 11.25).astype(int)
    np.testing.assert_array_equal(k, expected)
    assert np.bincount(k).tolist() == [11, 11, 12, 11, 11, 11, 12, 11, 11, 11, 12, 11, 11, 11, 12, 11]


def test_as_many_sectors_as_beams_gives_the_beams_back():
    scan = LaserScan(0.0, np.array([3.0, 1.0, 2.0, 5.0]), angle_min=-1.0, angle_increment=0.5)
    for reduce in ("min", "mean", "median", 30):
        assert laser_ring(scan, 4, reduce).tolist() == [3.0, 1.0, 2.0, 5.0]


def test_front_and_limits():
    # beams every 90 degrees all round; the robot's front at the laser's 90 degrees: from the front the
    # beams are at -90, 0, 90, 180; the ring starts at the first beam, or at the limits' low end
    angles = np.deg2rad([0, 90, 180, 270])
    assert sector_index(angles, 4, front=math.pi / 2).tolist() == [0, 1, 2, 3]
    assert sector_index(angles, 4, limits=(-math.pi, math.pi), front=math.pi / 2).tolist() == [1, 2, 3, 0]
    # only the front half (-90..90 from the front), in two sectors: right, left
    assert sector_index(angles, 2, limits=(-math.pi / 2, math.pi / 2), front=math.pi / 2).tolist() == [0, 1, 1, -1]


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 400), st.integers(1, 32), st.floats(-7.0, 7.0), st.floats(0.1, 2 * math.pi))
def test_sectors_are_contiguous_and_in_angle_order(n_beams, n_sectors, front, span):
    # a scan of any span short of a whole turn centred on the robot's front, the front anywhere
    assume(n_sectors <= n_beams)
    angles = -span / 2 + span / (n_beams - 1) * np.arange(n_beams)
    assume(not all_round(angles))
    k = sector_index(angles + front, n_sectors, front=front)
    # every beam in a sector, the sectors in angle order, each one a run of neighbouring beams
    assert k.min() == 0 and k.max() == n_sectors - 1 and np.all(np.diff(k) >= 0)
    assert np.all(np.diff(k) <= 1)


@pytest.mark.parametrize("n_beams", [360, 720, 1147])
def test_a_ring_all_round_starts_at_the_front_whatever_the_drivers_first_angle(n_beams):
    # one scene (a wall 1 m ahead within 10 degrees, 2 m to the left, 4 m elsewhere) seen by drivers that
    # start their beams at 0, at -pi and at +pi: the same ring, its first sector beginning at the front
    def scene(a):
        a = np.mod(a + np.pi, 2 * np.pi) - np.pi
        return np.where(np.abs(a) < np.deg2rad(10), 1.0, np.where(np.abs(a - np.pi / 2) < 0.3, 2.0, 4.0))

    rings = []
    for start in (0.0, -np.pi, np.pi):
        increment = 2 * np.pi / n_beams
        scan = LaserScan(0.0, scene(start + increment * np.arange(n_beams)), angle_min=start,
                         angle_increment=increment)
        rings.append(laser_ring(scan, 8))
    assert rings[0].tolist() == rings[1].tolist() == rings[2].tolist() == [1.0, 2.0, 2.0, 4.0, 4.0, 4.0, 4.0, 1.0]


def test_a_rear_laser_stays_in_one_piece():
    # a rear laser's beams from 90 to 270 degrees (through 180): two sectors, left-back then right-back
    angles = np.deg2rad(np.arange(90, 271, 45))
    assert sector_index(angles, 2).tolist() == [0, 0, 1, 1, 1]
    scan = LaserScan(0.0, np.array([1.0, 2.0, 3.0, 4.0, 5.0]), angle_min=math.pi / 2, angle_increment=math.pi / 4)
    assert laser_ring(scan, 5).tolist() == [1.0, 2.0, 3.0, 4.0, 5.0]


def test_sectors_without_a_beam_are_refused():
    with pytest.raises(ValueError, match="hold no beam"):
        sector_index(np.deg2rad([-10, 0, 10]), 8)


def test_reductions_by_hand():
    r = np.array([[4.0, 1.0, 2.0, 3.0, NAN, NAN]])
    idx = np.array([0, 0, 0, 0, 1, 1])
    assert reduce_sectors(r, idx, 2, "min").tolist() == [[1.0, INF]]        # an all-NaN sector saw nothing
    assert reduce_sectors(r, idx, 2, "mean").tolist() == [[2.5, INF]]
    assert reduce_sectors(r, idx, 2, "median").tolist() == [[2.5, INF]]
    # numpy's linear percentile of 1, 2, 3, 4: position 0.25 * 3 = 0.75 -> 1.75
    assert reduce_sectors(r, idx, 2, 25).tolist() == [[1.75, INF]]
    # an infinite beam: beyond it the percentile is infinite, before it finite
    r2 = np.array([1.0, 2.0, INF])
    assert reduce_sectors(r2, np.zeros(3, int), 1, 50).tolist() == [2.0]
    assert reduce_sectors(r2, np.zeros(3, int), 1, 60).tolist() == [INF]
    with pytest.raises(ValueError, match="reduce must be"):
        reduce_sectors(r2, np.zeros(3, int), 1, "max")


@settings(max_examples=30, deadline=None)
@given(st.lists(st.one_of(st.floats(0.05, 10.0), st.just(INF)), min_size=8, max_size=8))
def test_mean_clipped_at_the_threshold_preprocesses_to_the_mean_of_the_preprocessed_beams(ranges):
    idx = np.repeat([0, 1], 4)
    ring = reduce_sectors(ranges, idx, 2, "mean", clip=4.0)
    per_beam = preprocess(np.array(ranges), 4.0).reshape(2, 4).mean(axis=1)
    np.testing.assert_allclose(preprocess(ring, 4.0), per_beam, atol=1e-12)


def test_sonar_rings_by_time_in_mounting_order():
    rs = [RangeReading(0.0, 1.0, "front"), RangeReading(0.1, 2.0, "left"),
          RangeReading(0.2, 1.5, "front"),                     # front again: the newer reading
          RangeReading(0.3, -INF, "back", range_min=0.2), RangeReading(0.4, 9.0, "front", range_max=5.0),
          RangeReading(0.5, INF, "left"), RangeReading(0.6, 3.0, "back")]
    angles = {"front": 0.0, "left": math.pi / 2, "back": math.pi}
    rings = [(t, r.tolist()) for t, r in sonar_rings(rs, angles)]
    # a reading beyond range_max is no information: the ring reads +inf there (nothing seen)
    assert rings == [(0.3, [1.5, 2.0, 0.2]), (0.6, [INF, INF, 3.0])]


def test_sonar_rings_drop_stale_readings_and_name_strangers():
    rs = [RangeReading(0.0, 1.0, "a"), RangeReading(5.0, 2.0, "b"), RangeReading(5.1, 3.0, "a")]
    assert [(t, r.tolist()) for t, r in sonar_rings(rs, ["a", "b"], max_span=1.0)] == [(5.1, [3.0, 2.0])]
    with pytest.raises(ValueError, match="sensor 'c', not one of"):
        list(sonar_rings(rs + [RangeReading(6.0, 1.0, "c")], ["a", "b"]))


def test_sonar_sensors_found_in_natural_name_order():
    names = ["sonar10", "sonar2", "sonar1"]
    rs = [RangeReading(float(i), float(i), n) for i, n in enumerate(names * 2)]
    assert [r.tolist() for _, r in sonar_rings(rs)] == [[2.0, 1.0, 0.0], [5.0, 4.0, 3.0]]


def test_sonar_names_with_other_digits_sort_without_error():
    # superscripts are digits to str.isdigit() but not numbers to int(): "s1²" sorted before "s2"
    names = ["s2", "s1\u00b2", "s10"]
    rs = [RangeReading(float(i), float(i), n) for i, n in enumerate(names * 2)]
    assert [r.tolist() for _, r in sonar_rings(rs)] == [[1.0, 0.0, 2.0], [4.0, 3.0, 5.0]]
