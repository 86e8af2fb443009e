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
from dataclasses import dataclass, field

import numpy as np

from .geometry import ray_segment_distances
from .robot import NOMAD_200, Robot
from .world import WorldMap

__all__ = ["RunVariation", "Trajectory", "WallFollower", "WaypointFollower"]


@dataclass(frozen=True)
class RunVariation:
    """How much one run differs from another (standard deviations unless said).

    Parameters
    ----------
    speed : float, default=0.2
        Mean forward speed (m/s), approximately the speed of the paper's runs
        (10 m with a perception every 10 cm).
    speed_sd : float, default=0.1
        Run-to-run spread of the speed, as a fraction of ``speed``.
    speed_wobble : float, default=0.05
        Within-run speed fluctuation, as a fraction (slowly varying).
    offset_sd : float, default=0.04
        Run-to-run spread (m) of the distance kept from the wall.
    offset_wobble : float, default=0.02
        Within-run wander (m) of that distance (slowly varying, ~2 m correlation).
    heading_sd : float, default=0.03
        Standard deviation (rad/s) of the turn-rate jitter added to the
        controller's command (slowly varying, ~0.5 s correlation).
    start_sd : float, default=0.05
        Spread (m) of the starting point along and across the route.
    start_heading_sd : float, default=0.03
        Spread (rad) of the starting heading.
    """

    speed: float = 0.2
    speed_sd: float = 0.1
    speed_wobble: float = 0.05
    offset_sd: float = 0.04
    offset_wobble: float = 0.02
    heading_sd: float = 0.03
    start_sd: float = 0.05
    start_heading_sd: float = 0.03

    def none(self) -> "RunVariation":
        """The same speed with every random spread set to zero (for exact tests)."""
        return RunVariation(speed=self.speed, speed_sd=0.0, speed_wobble=0.0, offset_sd=0.0,
                            offset_wobble=0.0, heading_sd=0.0, start_sd=0.0, start_heading_sd=0.0)


@dataclass(frozen=True)
class Trajectory:
    """Poses at every control step.

    Attributes
    ----------
    t : ndarray of shape (n,)
        Time (s).
    poses : ndarray of shape (n, 3)
        x, y, heading.
    odometry : ndarray of shape (n,)
        Distance travelled (m).
    """

    t: np.ndarray
    poses: np.ndarray
    odometry: np.ndarray


def _ou(rng: np.random.Generator, n: int, dt: float, tau: float, sd: float) -> np.ndarray:
    """A stationary Ornstein-Uhlenbeck path: noise of standard deviation ``sd``, correlation time ``tau``."""
    z = rng.standard_normal(n + 1)  # drawn even when sd == 0, so every run uses the same draws
    if sd == 0.0:
        return np.zeros(n)
    a = math.exp(-dt / tau)
    b = sd * math.sqrt(1.0 - a * a)
    out = np.empty(n)
    x = sd * z[0]
    for i in range(n):
        x = a * x + b * z[i + 1]
        out[i] = x
    return out


@dataclass(frozen=True)
class _Drive:
    """The random draws of one run, shared by both controllers."""

    speed: np.ndarray
    offset: np.ndarray
    jitter: np.ndarray
    start: np.ndarray

    @classmethod
    def draw(cls, var: RunVariation, rng: np.random.Generator, n: int, dt: float) -> "_Drive":
        base_speed = var.speed * max(0.5, 1.0 + var.speed_sd * rng.standard_normal())
        base_offset = var.offset_sd * rng.standard_normal()
        start = np.array([var.start_sd * rng.standard_normal(), var.start_sd * rng.standard_normal(),
                          var.start_heading_sd * rng.standard_normal()])
        speed = base_speed * np.clip(1.0 + _ou(rng, n, dt, 3.0, var.speed_wobble), 0.5, 1.5)
        distance_tau = 2.0 / max(var.speed, 1e-6)  # about 2 m of travel
        offset = base_offset + _ou(rng, n, dt, distance_tau, var.offset_wobble)
        jitter = _ou(rng, n, dt, 0.5, var.heading_sd)
        return cls(speed, offset, jitter, start)


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


def _jittered_start(start, jitter) -> np.ndarray:
    """The nominal start moved along/across its heading and turned by the run's draws."""
    x0, y0, h0 = (float(v) for v in start)
    along, across, turn = jitter
    return np.array([x0 + along * math.cos(h0) + across * math.sin(h0),
                     y0 + along * math.sin(h0) - across * math.cos(h0), h0 + turn])


def _wrap(a: float) -> float:
    """A scalar angle wrapped into [-pi, pi) (the control loop's hot path)."""
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def _clip(v: float, limit: float) -> float:
    return -limit if v < -limit else (limit if v > limit else v)


def _step(pose: np.ndarray, speed: float, turn: float, dt: float, travelled: float) -> float:
    """Unicycle update of ``pose`` in place; returns the new odometry."""
    pose[2] = _wrap(pose[2] + turn * dt)
    step = speed * dt
    pose[0] += step * math.cos(pose[2])
    pose[1] += step * math.sin(pose[2])
    return travelled + step


@dataclass(frozen=True)
class WaypointFollower:
    """Pure pursuit along a polyline, shifted sideways by the run's offset.

    Parameters
    ----------
    waypoints : tuple of (x, y)
        The course.
    lookahead : float, default=0.6
        Pure-pursuit look-ahead distance (m).
    max_turn_rate : float, default=0.6
        Saturation of the turn-rate command (rad/s).
    dt : float, default=0.1
        Control period (s).
    """

    waypoints: tuple = field(default_factory=tuple)
    lookahead: float = 0.6
    max_turn_rate: float = 0.6
    dt: float = 0.1

    def drive(self, world: WorldMap, start, length: float, variation: RunVariation,
              rng: np.random.Generator, robot: Robot = NOMAD_200) -> Trajectory:
        path = np.asarray(self.waypoints, dtype=np.float64)
        seg = np.diff(path, axis=0)
        seg_len = np.linalg.norm(seg, axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg_len)])
        n_max = int(math.ceil(length / (0.4 * variation.speed) / self.dt)) + 2
        draws = _Drive.draw(variation, rng, n_max, self.dt)
        pose = _jittered_start(start, draws.start)
        poses, odo = [pose.copy()], [0.0]
        travelled = 0.0
        for i in range(n_max):
            s = _project(path, cum, pose[:2])
            target = _point_at(path, cum, seg, seg_len, min(s + self.lookahead, cum[-1]))
            # shift the carrot to the right of the course by the run's offset
            k = min(np.searchsorted(cum, s, side="right") - 1, len(seg) - 1)
            tangent = seg[k] / seg_len[k]
            target = target + draws.offset[i] * np.array([tangent[1], -tangent[0]])
            bearing = _wrap(math.atan2(target[1] - pose[1], target[0] - pose[0]) - pose[2])
            v = draws.speed[i]
            curvature = 2.0 * math.sin(bearing) / self.lookahead
            turn = _clip(v * curvature, self.max_turn_rate)
            travelled = _step(pose, v, turn + draws.jitter[i], self.dt, travelled)
            poses.append(pose.copy())
            odo.append(travelled)
            if travelled >= length:
                break
        else:
            raise RuntimeError("The waypoint follower did not cover the route length.")
        poses = np.array(poses)
        return Trajectory(np.arange(len(poses)) * self.dt, poses, np.array(odo))


def _project(path, cum, p) -> float:
    """Arc length along ``path`` of the point nearest ``p``."""
    a, b = path[:-1], path[1:]
    ab = b - a
    u = np.clip(np.sum((p - a) * ab, axis=1) / np.sum(ab * ab, axis=1), 0.0, 1.0)
    d = np.linalg.norm(a + u[:, None] * ab - p, axis=1)
    k = int(np.argmin(d))
    return float(cum[k] + u[k] * (cum[k + 1] - cum[k]))


def _point_at(path, cum, seg, seg_len, s) -> np.ndarray:
    k = int(min(np.searchsorted(cum, s, side="right") - 1, len(seg) - 1))
    return path[k] + seg[k] * ((s - cum[k]) / seg_len[k])


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
