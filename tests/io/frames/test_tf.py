"""The transform tree: chained lookups by hand, interpolation between samples, and refusals that name frames."""

import math
import tracemalloc

import pytest

from novelty.io.frames.tf import Placement, TfBuffer, TfError
from novelty.io.ros import caps
from novelty.io.ros.messages import Transform

QUARTER = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))   # 90 degrees about z


def tree():
    """map -> odom (moving) -> base_footprint (moving) -> base_link (static) -> laser (static, turned a quarter)."""
    tf = TfBuffer()
    tf.add(Transform(0.0, "base_footprint", "base_link", (0.0, 0.0, 0.1), (0, 0, 0, 1), static=True))
    tf.add(Transform(0.0, "base_link", "laser", (0.2, 0.0, 0.3), QUARTER, static=True))
    for t in (0.0, 1.0, 2.0):
        tf.add(Transform(t, "odom", "base_footprint", (t, 0.0, 0.0), (0, 0, math.sin(t / 4), math.cos(t / 4))))
    tf.add(Transform(0.5, "map", "odom", (10.0, 0.0, 0.0), (0, 0, 0, 1)))
    tf.add(Transform(1.5, "map", "odom", (10.0, 2.0, 0.0), (0, 0, 0, 1)))
    return tf


def test_a_chain_composed_by_hand():
    tf = tree()
    # at t = 1: base_footprint at x = 1 turned 0.5 rad in odom; base_link 0.1 above; the laser 0.2 ahead of it
    laser = tf.lookup("odom", "laser", 1.0)
    assert laser.translation == pytest.approx((1 + 0.2 * math.cos(0.5), 0.2 * math.sin(0.5), 0.4))
    assert laser.planar[2] == pytest.approx(0.5 + math.pi / 2)
    # the other way round, and between two branches' frames
    back = tf.lookup("laser", "odom", 1.0).then(laser)
    assert back.translation == pytest.approx((0, 0, 0), abs=1e-12) and back.planar[2] == pytest.approx(0, abs=1e-12)
    assert tf.lookup("base_link", "laser", 7.0).translation == pytest.approx((0.2, 0.0, 0.3))   # static: any time
    assert tf.chain("laser") == ["laser", "base_link", "base_footprint", "odom", "map"]
    assert tf.describe() == "map -> odom -> base_footprint -> base_link -> laser"


def test_moving_edges_are_interpolated_and_held_only_briefly():
    tf = tree()
    # halfway between the samples at 0 and 1 s (yaw t / 2): x = 0.5, yaw = 0.25 (slerp of 0 and 0.5)
    mid = tf.lookup("odom", "base_footprint", 0.5)
    assert mid.translation == pytest.approx((0.5, 0.0, 0.0)) and mid.planar[2] == pytest.approx(0.25)
    # map -> odom: y from 0 at 0.5 s to 2 at 1.5 s; at 1 s, 1
    assert tf.lookup("map", "base_footprint", 1.0).translation[1] == pytest.approx(1.0 + math.sin(0.0))
    assert tf.lookup("odom", "base_footprint", 2.1).translation[0] == pytest.approx(2.0)   # held 0.1 s after
    with pytest.raises(TfError, match=r"odom -> base_footprint is asked for at 2.500 s, 0.500 s after its last "
                                      r"\(0.000 to 2.000 s held, 0.2 s tolerated\)"):
        tf.lookup("odom", "base_footprint", 2.5)
    assert tf.newest("map", "laser") == 1.5 and tf.newest("base_link", "laser") == math.inf


def test_refusals_name_the_frames_and_the_tree():
    tf = tree()
    tf.add(Transform(0.0, "world", "camera", (0, 0, 0), (0, 0, 0, 1), static=True))
    with pytest.raises(TfError, match=r"No transform names frame 'base_scan' \(the source\); the tree: "
                                      r"world -> camera; map -> odom"):
        tf.lookup("odom", "base_scan", 1.0)
    with pytest.raises(TfError, match=r"Frames 'odom' and 'camera' are in two trees: map -> odom and world -> camera"):
        tf.lookup("odom", "camera", 1.0)
    with pytest.raises(TfError, match="needs two different frames"):
        tf.add(Transform(0.0, "a", "a", (0, 0, 0), (0, 0, 0, 1)))


def test_old_samples_are_forgotten_beyond_the_cache():
    tf = TfBuffer(cache=1.0)
    for k in range(100):
        tf.add(Transform(k * 0.1, "odom", "base_link", (k * 0.1, 0, 0), (0, 0, 0, 1)))
    # forgotten in batches: once samples are 2 s old, all but the last second's (and one before it, for
    # interpolating into it); at most 3 s are held
    edge = tf._edges["base_link"]
    assert edge.times[-1] - edge.times[0] <= 2.0 + 1e-9 and len(edge.times) <= 31
    assert tf.lookup("odom", "base_link", 9.0).translation[0] == pytest.approx(9.0)
    with pytest.raises(TfError, match="before its first"):
        tf.lookup("odom", "base_link", 6.0)


def test_placements_compose_and_invert():
    p = Placement((1.0, 2.0, 0.0), QUARTER)
    assert p.inverse().then(p).translation == pytest.approx((0, 0, 0), abs=1e-12)
    # a point 1 m ahead of the child is (1, 3) in the parent: the child faces +y
    assert p.then(Placement((1.0, 0.0, 0.0))).translation == pytest.approx((1.0, 3.0, 0.0))


def test_samples_denser_than_the_resolution_are_thinned_and_still_interpolate():
    tf = TfBuffer()
    tracemalloc.start()
    try:
        for k in range(200_000):   # 0.2 s of an edge published every microsecond
            t = 1.0 + k * 1e-6
            tf.add(Transform(t, "odom", "base_link", (t, 2 * t, 0.0), (0, 0, 0, 1)))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    times = tf._edges["base_link"].times
    assert len(times) <= 0.2 / (4 * tf.cache / caps.MAX_TF_SAMPLES) * 2 + 2 and peak < 10 * 2**20
    assert times[-1] == 1.0 + 199_999 * 1e-6   # the newest is always kept
    assert tf.lookup("odom", "base_link", 1.1234567).translation == pytest.approx((1.1234567, 2.2469134, 0.0))


def test_a_chain_deeper_than_the_bound_is_refused_by_the_transform_that_makes_it():
    tf = TfBuffer()
    for k in range(caps.MAX_TF_DEPTH - 1):
        tf.add(Transform(0.0, f"f{k}", f"f{k + 1}", (1.0, 0, 0), (0, 0, 0, 1), static=True))
    assert len(tf.chain(f"f{caps.MAX_TF_DEPTH - 1}")) == caps.MAX_TF_DEPTH
    with pytest.raises(TfError, match=rf"f{caps.MAX_TF_DEPTH - 1} -> f{caps.MAX_TF_DEPTH} at 0.000 s: makes a "
                                      rf"chain of {caps.MAX_TF_DEPTH + 1} frames; at most {caps.MAX_TF_DEPTH} are "
                                      r"read \(novelty.io.ros.caps.MAX_TF_DEPTH\)"):
        tf.add(Transform(0.0, f"f{caps.MAX_TF_DEPTH - 1}", f"f{caps.MAX_TF_DEPTH}", (1.0, 0, 0), (0, 0, 0, 1)))
    # and a parent moved under a deep chain's leaf: the frames below it count too
    with pytest.raises(TfError, match="makes a chain of"):
        tf.add(Transform(0.0, "deep", "f0", (1.0, 0, 0), (0, 0, 0, 1), static=True))
    assert tf.parent("f0") is None and tf.lookup("f0", f"f{caps.MAX_TF_DEPTH - 1}", 0.0).translation[0] == 99.0


@pytest.mark.parametrize("rotation, translation, says", [
    ((0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), "a zero quaternion"),
    ((0.0, 0.0, 0.0, math.nan), (0.0, 0.0, 0.0), "a rotation that is not finite"),
    ((0.0, 0.0, 0.0, 1.0), (math.inf, 0.0, 0.0), "a translation that is not finite"),
])
def test_a_transform_without_a_placement_is_refused_saying_why(rotation, translation, says):
    with pytest.raises(TfError, match=f"odom -> base_link at 1.000 s: {says}"):
        TfBuffer().add(Transform(1.0, "odom", "base_link", translation, rotation))


def test_a_loop_or_a_tree_beyond_its_frames_is_refused_by_the_transform_that_makes_it(monkeypatch):
    tf = tree()
    with pytest.raises(TfError, match=r"laser -> map at 2.000 s: makes a loop \(map -> odom -> base_footprint -> "
                                      r"base_link -> laser -> map\)"):
        tf.add(Transform(2.0, "laser", "map", (0, 0, 0), (0, 0, 0, 1)))
    assert tf.chain("laser") == ["laser", "base_link", "base_footprint", "odom", "map"]   # as it was
    monkeypatch.setattr(caps, "MAX_TF_FRAMES", 6)
    tf.add(Transform(0.0, "base_link", "sonar", (0, 0, 0), (0, 0, 0, 1), static=True))
    with pytest.raises(TfError, match=r"base_link -> camera at 0.000 s: the tree would name 7 frames; at most 6"):
        tf.add(Transform(0.0, "base_link", "camera", (0, 0, 0), (0, 0, 0, 1), static=True))
