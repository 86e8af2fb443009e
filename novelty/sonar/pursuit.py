"""Driving a course by pure pursuit (Coulter, 1992): the control environment's waypoint follower.

References
----------
Coulter, R. C. (1992). Implementation of the pure pursuit path tracking
algorithm. Technical report CMU-RI-TR-92-01, Carnegie Mellon University.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .driving import RunVariation, Trajectory, _clip, _Drive, _jittered_start, _step, _wrap
from .robot import NOMAD_200, Robot
from .world import WorldMap

__all__ = ["WaypointFollower"]


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
