"""Plane geometry of the sonar model, answers known: ray-segment distances, mirror reflection, elevation."""

import math

import numpy as np
import pytest

from novelty.sonar.geometry import elevation_offset, mirror, ray_segment_distances


def test_ray_hits_segment_at_known_distance_and_misses_behind():
    t = ray_segment_distances(np.array([[0.0, 0.0], [0.0, 0.0]]),
                              np.array([[1.0, 0.0], [-1.0, 0.0]]),
                              np.array([[3.0, -1.0]]), np.array([[3.0, 1.0]]))
    assert t[0, 0] == pytest.approx(3.0)
    assert np.isinf(t[1, 0])


def test_mirror_reflects_in_the_normal():
    d = np.array([[math.cos(math.radians(-30)), math.sin(math.radians(-30))]])
    out = mirror(d, np.array([[0.0, 1.0]]))
    assert out[0] == pytest.approx([math.cos(math.radians(30)), math.sin(math.radians(30))])


def test_elevation_offset_zero_when_surface_spans_sensor_height():
    e = elevation_offset(np.array([1.0, 1.0]), np.array([0.0, 0.0]), np.array([2.0, 0.4]), 0.72)
    assert e[0] == 0.0
    assert e[1] == pytest.approx(math.atan2(0.32, 1.0))
