"""A drive up and down a corridor, as sweeps and as a CARMEN log: the walls are boxes cast into empty scans."""

import math

import numpy as np
import pytest

from novelty.tasks.objects.raycast import inject
from novelty.tasks.objects.shapes import Wall
from novelty.io.ros.messages import Sweep

#: The corridor: 2 m wide along x from -1 to 11, closed at both ends.
WALLS = [Wall("left", -1.0, 1.05, 11.0, 1.05), Wall("right", -1.0, -1.05, 11.0, -1.05),
         Wall("near end", -1.05, -1.0, -1.05, 1.0), Wall("far end", 11.05, -1.0, 11.05, 1.0)]
#: A 180-degree laser of 37 beams, 5 degrees apart.
ANGLES = np.deg2rad(np.arange(-90.0, 90.1, 5.0))


def drive_poses(legs: int = 4, step: float = 0.5) -> np.ndarray:
    """Up and down the corridor's middle, ``legs`` times, a scan every ``step`` m: out facing +x, back facing -x."""
    out = np.arange(0.0, 10.0 + step / 2, step)
    poses = []
    for leg in range(legs):
        xs = out if leg % 2 == 0 else out[::-1]
        poses += [[x, 0.0, 0.0 if leg % 2 == 0 else math.pi] for x in xs]
    return np.array(poses)


def corridor_sweeps(legs: int = 4) -> list:
    """The drive's sweeps: the walls' ranges along every beam (the walls stand throughout)."""
    sweeps = []
    for i, pose in enumerate(drive_poses(legs)):
        empty = Sweep(float(i), np.zeros((len(ANGLES), 2)), ANGLES, np.full(len(ANGLES), np.inf), pose)
        sweeps.append(inject(empty, WALLS).sweep)
    return sweeps


@pytest.fixture
def drive():
    return corridor_sweeps()


@pytest.fixture
def drive_log(tmp_path):
    """The drive as a CARMEN log of FLASER messages (37 beams over 180 degrees), one a second."""
    path = tmp_path / "corridor.log"
    lines = []
    for s in corridor_sweeps():
        x, y, theta = s.pose
        ranges = " ".join(f"{r:.6f}" for r in s.ranges)
        lines.append(f"FLASER {len(s.ranges)} {ranges} {x} {y} {theta} {x} {y} {theta} {s.time} host {s.time}\n")
    path.write_text("".join(lines))
    return path
