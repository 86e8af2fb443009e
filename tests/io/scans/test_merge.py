"""Merging several sensors' sweeps within a tolerance: the pairs made, the strays dropped."""

import numpy as np
import pytest

from novelty.io.scans.merge import Merger, merged
from novelty.io.ros.messages import Sweep


def sweep(t, source, ranges=(1.0,)):
    n = len(ranges)
    return Sweep(t, np.zeros((n, 2)), np.linspace(0, 1, n), np.array(ranges, float), np.array([t, 0, 0]),
                 "base_link", source)


def test_sweeps_within_the_tolerance_are_merged_in_time_order():
    m = Merger(["/a", "/b"], tolerance=0.05)
    out = [m.push(src, sweep(t, src)) for t, src in [(0.0, "/a"), (0.02, "/b"), (0.1, "/a"), (0.3, "/b"),
                                                    (0.31, "/a")]]
    assert [None if o is None else (o.time, o.source) for o in out] == [None, (0.0, "/a,/b"), None, None,
                                                                       (0.3, "/a,/b")]
    assert (m.merged, m.dropped) == (2, 1)   # the /a at 0.1 s found no /b within 0.05 s


def test_a_merged_sweep_holds_every_beam():
    whole = merged([sweep(1.0, "/a", (1.0, 2.0)), sweep(0.9, "/b", (3.0,))])
    assert whole.ranges.tolist() == [1.0, 2.0, 3.0] and whole.origins.shape == (3, 2)
    assert whole.time == 0.9 and whole.pose.tolist() == [0.9, 0, 0] and whole.source == "/a,/b"
    with pytest.raises(ValueError, match="tolerance"):
        Merger(["/a"], tolerance=-1)


def test_the_joined_geometry_is_kept_while_the_parts_share_theirs():
    a, b = sweep(0.0, "/a", (1.0, 2.0)), sweep(0.01, "/b", (3.0,))
    for s in (a, b):
        s.origins.flags.writeable = s.angles.flags.writeable = False
    kept = {}
    first = merged([a, b], kept)
    again = merged([Sweep(0.1, a.origins, a.angles, np.array([5.0, 6.0]), None), b], kept)
    assert again.angles is first.angles and again.origins is first.origins and not again.angles.flags.writeable
    assert again.ranges.tolist() == [5.0, 6.0, 3.0]
    other = merged([sweep(0.2, "/a", (1.0, 2.0)), b], kept)   # writeable parts: joined afresh, nothing kept
    assert other.angles is not first.angles
