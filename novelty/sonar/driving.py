"""What both route controllers share: a run's random variation, its draws, and the unicycle step.

:class:`RunVariation` says how much one run differs from another (start,
speed, distance kept, heading jitter); ``_Drive`` draws a run's values from a
seeded generator; ``_step`` moves the robot one control period. The
controllers are :class:`~novelty.sonar.controller.WallFollower` and
:class:`~novelty.sonar.pursuit.WaypointFollower`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RunVariation", "Trajectory"]


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
