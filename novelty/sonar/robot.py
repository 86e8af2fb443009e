"""The robot: a Nomad 200-like base with a ring of 16 sonars.

The Nomad 200 is a round robot 18 in (0.46 m) across with a ring of 16
Polaroid sonars, 22.5 degrees apart, at the top of its turret, and a band of
16 infra-red proximity sensors at the bottom of the turret (Nomadic
Technologies, 1997). Marsland et al. (2000, section 4.1) kept the turret
fixed to the base, so the sonars turn with the direction of travel, used the
infra-red band to follow walls and the sonars as the novelty filter's input.

Sensor ``i`` points ``i * 22.5`` degrees counter-clockwise from straight
ahead: sensor 0 faces forward, 4 left, 8 backward, 12 right (the followed
wall).

References
----------
Nomadic Technologies (1997). Nomad 200 User's Guide. Mountain View, CA.

Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, section 4.1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Robot", "NOMAD_200"]


@dataclass(frozen=True)
class Robot:
    """Body and sensor placement.

    Parameters
    ----------
    diameter : float, default=0.46
        Base diameter (m); 18 in for the Nomad 200 (Nomadic Technologies, 1997).
    n_sonars : int, default=16
        Sonars evenly spaced round the turret (22.5 degrees apart for 16).
    sonar_ring_radius : float, default=0.2
        Distance (m) of each transducer from the robot's centre; approximately
        the turret's radius.
    sonar_height : float, default=0.72
        Height (m) of the sonar ring above the floor; approximately the top of
        the Nomad 200's turret. Objects lower than the beam's lower edge (a box
        in a doorway) are not heard.
    ir_height : float, default=0.35
        Height (m) of the infra-red band at the bottom of the turret,
        approximately.
    ir_range : float, default=0.85
        Largest distance (m) from the robot's centre at which the infra-red
        sensors see a surface: about 24 in beyond the 0.23 m radius, the
        Nomad's infra-red range (Nomadic Technologies, 1997), approximately.
    ring_period : float, default=0.25
        Time (s) to fire the whole sonar ring once. The ring is fired one
        transducer after another; 16 firings of about 15 ms each,
        approximately. The robot moves about 5 cm per ring at 0.2 m/s, so
        about two rings fall in each 10 cm of travel.
    """

    diameter: float = 0.46
    n_sonars: int = 16
    sonar_ring_radius: float = 0.2
    sonar_height: float = 0.72
    ir_height: float = 0.35
    ir_range: float = 0.85
    ring_period: float = 0.25

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    def sonar_angles(self) -> np.ndarray:
        """Direction of each sonar relative to the heading (radians, CCW from ahead)."""
        return np.arange(self.n_sonars) * (2.0 * math.pi / self.n_sonars)

    def sonar_poses(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions (p, n_sonars, 2) and axis angles (p, n_sonars) of every transducer.

        ``poses`` is (p, 3): x, y, heading.
        """
        poses = np.atleast_2d(np.asarray(poses, dtype=np.float64))
        angles = poses[:, 2:3] + self.sonar_angles()[None, :]
        pos = poses[:, None, :2] + self.sonar_ring_radius * np.stack(
            [np.cos(angles), np.sin(angles)], axis=-1)
        return pos, angles


#: The paper's robot with the defaults above.
NOMAD_200 = Robot()
