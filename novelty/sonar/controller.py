"""Driving a route: a right-hand wall follower and a waypoint follower, with run-to-run variation.

Marsland et al. (2000, section 4) moved the robot with a pre-trained
infra-red wall-following behaviour (Nehmzow, 1994) along the right-hand
wall for 10 m; in the control environment it was steered along a course.
Neither is repeatable to the centimetre: the starting position, the
distance kept from the wall, the speed and small heading errors change from
run to run, and the paper shows the effect (a thin crack perceived in some
runs and not in others). :class:`RunVariation` draws these from a seeded
generator; the controllers turn them into a trajectory.

:class:`WallFollower` senses the wall with three infra-red rays (right,
right-front, right-rear) at the height of the infra-red band, estimates the
wall's distance and direction, and steers with a saturated
proportional law; where the wall is out of infra-red range (an open door, a
deep recess, a junction) it holds its course. :class:`WaypointFollower` is
a pure-pursuit controller on a polyline (Coulter, 1992).

The run's variation and the step both controllers share are in
:mod:`novelty.sonar.driving`, the waypoint follower in
:mod:`novelty.sonar.pursuit`; their names are importable from here too.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, sections 4.1-4.2.

Nehmzow, U. (1994). Autonomous acquisition of sensor-motor couplings in
robots. Technical report UMCS-94-11-1, University of Manchester.

Coulter, R. C. (1992). Implementation of the pure pursuit path tracking
algorithm. Technical report CMU-RI-TR-92-01, Carnegie Mellon University.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .driving import RunVariation, Trajectory, _clip, _Drive, _jittered_start, _step, _wrap
from .geometry import ray_segment_distances
from .pursuit import WaypointFollower
from .robot import NOMAD_200, Robot
from .world import WorldMap

__all__ = ["RunVariation", "Trajectory", "WallFollower", "WaypointFollower"]


@dataclass(frozen=True)
class WallFollower:
    """Keep the right-hand wall at ``distance`` with infra-red rays.

    The wall's direction is tracked as a running average of the line through
    the right-front and right-rear infra-red hits, updated only by estimates
    within ``consistency`` of it (so the sides of a door recess, which give
    wild estimates, are ignored). The desired heading is that direction
    turned towards the wall by ``gain_distance * (d - distance)``, at most
    ``max_correction``; the turn rate steers the heading to it. Where the
    wall is out of infra-red range the robot holds the tracked direction.

    Parameters
    ----------
    distance : float, default=0.55
        Distance (m) from the robot's centre to the followed wall
        (about 0.3 m of clearance for the 0.46 m base), approximately.
    gain_distance : float, default=1.0
        Heading correction (rad) per metre of distance error.
    max_correction : float, default=0.2
        Largest heading correction (rad, about 11 degrees).
    gain_heading : float, default=1.5
        Turn rate (rad/s) per radian of heading error.
    max_turn_rate : float, default=0.4
        Saturation of the turn-rate command (rad/s).
    consistency : float, default=0.25
        Largest disagreement (rad) between a new wall-direction estimate and
        the tracked one for the estimate to be used.
    memory : float, default=1.5
        Time constant (s) of the wall-direction average.
    dt : float, default=0.1
        Control period (s): a 10 Hz loop, approximately the rate at which the
        Nomad's infra-red ring is read.
    """

    distance: float = 0.55
    gain_distance: float = 1.0
    max_correction: float = 0.2
    gain_heading: float = 1.5
    max_turn_rate: float = 0.4
    consistency: float = 0.25
    memory: float = 1.5
    dt: float = 0.1

    def drive(self, world: WorldMap, start, length: float, variation: RunVariation,
              rng: np.random.Generator, robot: Robot = NOMAD_200) -> Trajectory:
        """Follow the wall from pose ``start`` until ``length`` metres are travelled."""
        n_max = int(math.ceil(length / (0.4 * variation.speed) / self.dt)) + 2
        draws = _Drive.draw(variation, rng, n_max, self.dt)
        pose = _jittered_start(start, draws.start)
        wall_dir = float(start[2])  # the robot is set down parallel to the wall
        blend = self.dt / self.memory
        ir = _InfraRed(world, robot)
        poses, odo = [pose.copy()], [0.0]
        travelled = 0.0
        for i in range(n_max):
            d, direction = ir.right_wall(pose)
            if direction is not None and abs(_wrap(direction - wall_dir)) < self.consistency:
                wall_dir += blend * _wrap(direction - wall_dir)
            desired = wall_dir
            if d is not None:
                error = d - (self.distance + draws.offset[i])   # too far: turn right
                desired -= _clip(self.gain_distance * error, self.max_correction)
            turn = _clip(self.gain_heading * _wrap(desired - pose[2]), self.max_turn_rate)
            turn += draws.jitter[i]
            travelled = _step(pose, draws.speed[i], turn, self.dt, travelled)
            poses.append(pose.copy())
            odo.append(travelled)
            if travelled >= length:
                break
        else:
            raise RuntimeError("The wall follower did not cover the route length.")
        poses = np.array(poses)
        return Trajectory(np.arange(len(poses)) * self.dt, poses, np.array(odo))


class _InfraRed:
    """Three infra-red rays to the right, seeing surfaces that reach the band's height.

    Segments are bucketed on a 1 m grid (each cell lists those within
    infra-red range of it), so each control step tests only a handful.
    """

    ANGLES = np.radians([-90.0, -45.0, -135.0])
    CELL = 1.0

    def __init__(self, world: WorldMap, robot: Robot):
        props = world.material_table()
        z = world.z
        keep = ~props["transparent"] & (z[:, 0] <= robot.ir_height) & (z[:, 1] >= robot.ir_height)
        self.p0 = world.p0[keep]
        self.p1 = world.p1[keep]
        self.range = robot.ir_range
        self._cells: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}

    def _near(self, x: float, y: float):
        key = (int(math.floor(x / self.CELL)), int(math.floor(y / self.CELL)))
        if key not in self._cells:
            lo = np.array(key, dtype=np.float64) * self.CELL - self.range
            hi = lo + self.CELL + 2 * self.range
            seg_lo = np.minimum(self.p0, self.p1)
            seg_hi = np.maximum(self.p0, self.p1)
            idx = np.flatnonzero(np.all((seg_hi >= lo) & (seg_lo <= hi), axis=1))
            self._cells[key] = (self.p0[idx], self.p1[idx])
        return self._cells[key]

    def right_wall(self, pose):
        """(distance, direction) of the right-hand wall; ``None`` for what is out of range."""
        p0, p1 = self._near(pose[0], pose[1])
        if p0.shape[0] == 0:
            return None, None
        ang = pose[2] + self.ANGLES
        dirs = np.stack([np.cos(ang), np.sin(ang)], axis=1)
        origin = np.repeat(pose[None, :2], 3, axis=0)
        t = ray_segment_distances(origin, dirs, p0, p1).min(axis=1)
        seen = t <= self.range
        if seen[1] and seen[2]:
            front = origin[1] + t[1] * dirs[1]
            rear = origin[2] + t[2] * dirs[2]
            along = front - rear
            direction = math.atan2(along[1], along[0])
            # the distance from the centre to the line through the two hits
            rel = pose[:2] - rear
            dist = abs(along[0] * rel[1] - along[1] * rel[0]) / max(math.hypot(*along), 1e-9)
            return dist, direction
        if seen[0]:
            return float(t[0]), None
        return None, None
