"""Assembling fragments: patterns found, stated, or absent; incomplete revolutions counted, never reduced."""

import math

import numpy as np
import pytest

from novelty.io.scans.assembly import LEARN, Assembler
from novelty.io.ros.messages import LaserScan

INC = math.radians(0.5)


def fragments(per, revolutions, span=270, first=0, drop=(), frame="laser"):
    """``per`` fragments a revolution of ``span`` degrees; fragment f of revolution k reads f + 10 k."""
    beams = int(span / 0.5) // per
    out = []
    for k in range(revolutions):
        for f in range(per):
            if (k == 0 and f < first) or (k, f) in drop:
                continue
            start = math.radians(-span / 2) + f * beams * INC
            out.append(LaserScan(k + 0.01 * f, np.full(beams, f + 10.0 * k), start, INC, frame=frame))
    return out


def assemble(scans, **kw):
    a = Assembler(**kw)
    out = [w for s in scans for w in a.push(s)] + list(a.flush())
    return a, out


def test_a_revolution_in_six_fragments_from_mid_revolution():
    a, out = assemble(fragments(6, 30, first=2))
    assert (a.messages, a.scans, a.incomplete, a.per_revolution) == (178, 29, 1, 6)
    # the first whole revolution is the second: its fragments in order, from -135 degrees
    assert out[0].ranges[::90].tolist() == [10.0, 11.0, 12.0, 13.0, 14.0, 15.0]
    assert out[0].angle_min == pytest.approx(math.radians(-135)) and out[0].stamp == 1.0


def test_a_dropped_or_late_fragment_leaves_its_revolution_out():
    a, out = assemble(fragments(6, 10, drop={(4, 3)}))
    assert [round(w.stamp) for w in out] == [0, 1, 2, 3, 5, 6, 7, 8, 9] and a.incomplete == 1


def test_all_round_fragments_start_at_the_smallest_angle():
    a, out = assemble(fragments(4, 5, span=360, first=1))
    assert a.per_revolution == 4 and out[0].angle_min == pytest.approx(-math.pi) and a.incomplete == 1


@pytest.mark.parametrize("n", [5, LEARN + 7])
def test_whole_scans_and_unrelated_geometries_pass_through(n):
    # fewer messages than the pattern is learned from, and more: every one comes through, in order
    whole = [LaserScan(float(k), np.ones(10), -1.0, 0.2) for k in range(n)]
    a, out = assemble(whole)
    assert out == whole and a.per_revolution == 1 and (a.messages, a.scans, a.incomplete) == (n, n, 0)
    # two geometries that overlap rather than tile: each message whole
    odd = [LaserScan(float(k), np.ones(10), -1.0 + 0.5 * (k % 2), 0.2) for k in range(6)]
    a, out = assemble(odd)
    assert len(out) == 6 and a.per_revolution == 1


def test_stated_counts():
    assert assemble(fragments(6, 3), fragments=1)[0].scans == 18
    with pytest.raises(ValueError, match="4 fragments a revolution were stated, but its first messages tile a "
                                         "revolution in 6"):
        assemble(fragments(6, 3), fragments=4, topic="/scan")
    with pytest.raises(ValueError, match="fragments must be 'auto' or a count"):
        Assembler(fragments=0)


def test_a_revolution_starting_at_float32_minus_pi_starts_there():
    # a driver's float32 angles: the first fragment's angle_min is float32(-pi), a hair below -pi
    inc = float(np.float32(INC))
    scans = []
    for k in range(6):
        for f in range(4):
            start = float(np.float32(-math.pi + f * 180 * inc))
            scans.append(LaserScan(k + 0.01 * f, np.full(180, f + 10.0 * k), start, inc, frame="laser"))
    a, out = assemble(scans)
    assert a.per_revolution == 4 and a.incomplete == 0
    assert [w.stamp for w in out] == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]   # each its own revolution's first fragment
    assert out[1].ranges[::180].tolist() == [10.0, 11.0, 12.0, 13.0]


def test_fragments_spanning_more_than_one_turn_are_not_one_revolution():
    # 8 fragments of 181 degrees, each starting where the one before ended: four turns and more
    scans = [LaserScan(k + 0.01 * f, np.ones(362), math.radians((f * 181 + 180) % 360 - 180), INC)
             for k in range(20) for f in range(8)]
    a, out = assemble(scans)
    assert a.per_revolution == 1 and len(out) == len(scans)
    with pytest.raises(ValueError, match="8 fragments a revolution were stated, but its first .* messages do not "
                                         "tile a revolution"):
        assemble(scans, fragments=8, topic="/scan")
