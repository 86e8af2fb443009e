"""The fast ring of a sweep against its readable reference: every end point's bearing computed."""

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from novelty.io.ros.messages import Sweep
from novelty.io.scans.sweep_rings import RingMaker, reference_ring


@settings(max_examples=80, deadline=None)
@given(st.integers(16, 400), st.floats(0.5, 2 * math.pi), st.floats(-4.0, 4.0), st.integers(1, 16),
       st.sampled_from(["min", "mean", 30.0]), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.booleans(),
       st.booleans(), st.integers(0, 2**32 - 1))
def test_offset_sweeps_give_the_reference_ring(n, span, start, sectors, reduce, ox, oy, limited, two, seed):
    assume(sectors <= n // 2)
    rng = np.random.default_rng(seed)
    angles = start + span / n * np.arange(n)
    ranges = rng.choice([0.05, 0.3, 1.0, 2.5, 7.0, np.inf, np.nan], n) * rng.uniform(0.5, 1.5, n)
    origins = np.tile([ox, oy], (n, 1))
    if two:   # a second sensor's beams from elsewhere, as a merged sweep holds them
        origins[n // 2:] = [-oy, ox]
    origins.flags.writeable = False
    sweep = Sweep(0.0, origins, angles, ranges, None)
    limits = (-1.0, 1.5) if limited else None
    try:
        expected = reference_ring(sweep, sectors, reduce, limits, front=0.2)
    except ValueError:
        return   # sectors the beams cannot fill: refused alike (tested elsewhere)
    make = RingMaker(sectors, reduce, limits, front=0.2)
    for _ in range(2):   # the second time from what the first kept
        np.testing.assert_allclose(make(sweep), expected, rtol=1e-12, atol=1e-12)


def test_a_beam_near_a_boundary_is_placed_by_its_end_point():
    # two sectors meeting straight ahead; a laser 0.2 m to the left looking 1 degree right of ahead:
    # its beam's end point 1 m along is at (1.0, 0.18), left of ahead: the left sector
    angles = np.array([-1.5, -0.017453292519943295, 1.5])
    sweep = Sweep(0.0, np.tile([0.0, 0.2], (3, 1)), angles, np.array([np.inf, 1.0, np.inf]), None)
    ring = RingMaker(2, limits=(-math.pi / 2, math.pi / 2))(sweep)
    assert ring[0] == np.inf and ring[1] == math.hypot(math.cos(angles[1]), 0.2 + math.sin(angles[1]))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=32), st.just(0.1), st.just(10.0)),
                min_size=1, max_size=60), st.floats(0.0, 1.0), st.floats(1.0, 20.0), st.booleans())
def test_the_compiled_cleaning_is_clean_ranges(ranges, range_min, range_max, single):
    from novelty.io.scans._sweep_kernels import clean_into
    from novelty.io.scans.ranges import clean_ranges

    given_ranges = np.array(ranges, dtype=np.float32 if single else np.float64)
    out = np.empty(len(given_ranges))
    clean_into(given_ranges, range_min, range_max, out)
    np.testing.assert_array_equal(out, clean_ranges(given_ranges, range_min, range_max))
