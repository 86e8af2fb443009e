"""Where a sensor sits on the robot: a planar scan's beams moved into the robot's base frame.

A laser measures in its own frame: beam ``i`` leaves the frame's origin along
``(cos a_i, sin a_i, 0)``. Its mount (the sensor frame's placement in the base
frame: a translation and a full 3-D rotation, from ``tf`` or stated by the
user) turns each beam's direction ``d`` into ``R d`` from the origin ``t``.
Seen from above (the base frame's x-y plane, REP 103), the beam starts at
``(t_x, t_y)``, points along ``atan2((R d)_y, (R d)_x)`` and a range ``r``
covers ``r * |(R d)_xy|`` of the floor plane:

- an upside-down laser (rolled 180 degrees about x) has ``R (cos a, sin a, 0)
  = (cos a, -sin a, 0)``: its beams sweep clockwise, its ring mirrored unless
  the mount is applied;
- a laser turned by ``yaw`` about z has its beams turned by ``yaw``;
- a laser tilted by ``theta`` about y sees the floor plane foreshortened by
  ``cos theta`` ahead; one tilted beyond :data:`MAX_TILT` is not a planar
  scanner of the robot's surroundings and is refused.

The directions are unwrapped along the beams, so that a scan crossing the
robot's back (+-180 degrees) stays in one piece.

References
----------
REP 103 (frames: x forward, y left, z up; angles counter-clockwise);
REP 105 (``base_link`` and the sensors' frames below it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..ros.quaternions import matrix, multiply, normalized
from .tf import Placement

__all__ = ["Mount", "MAX_TILT", "parse_mount"]

#: The largest angle (rad) between a laser's scan plane and the floor plane that is read as a planar scan.
MAX_TILT = math.radians(30.0)


@dataclass(frozen=True)
class Mount:
    """A sensor's placement in the robot's base frame, and where it came from (``tf``, an option, assumed)."""

    placement: Placement = Placement()
    origin: str = "assumed"

    @classmethod
    def planar(cls, x: float = 0.0, y: float = 0.0, yaw: float = 0.0, flipped: bool = False,
               origin: str = "option") -> "Mount":
        """A sensor at ``(x, y)`` (m) facing ``yaw`` (rad), upside down (rolled 180 degrees about x) if ``flipped``."""
        turn = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
        rotation = multiply(turn, (1.0, 0.0, 0.0, 0.0)) if flipped else turn
        return cls(Placement((float(x), float(y), 0.0), normalized(rotation)), origin)

    @property
    def centred(self) -> bool:
        """At the base frame's origin, facing forward, upright: the beams are the base frame's as they are."""
        p = self.placement
        return p.translation[:2] == (0.0, 0.0) and p.rotation == (0.0, 0.0, 0.0, 1.0)

    def beams(self, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The beams at ``angles`` (sensor frame) in the base frame: origins (n, 2), directions, range scale.

        A range ``r`` along a beam covers ``r * scale`` of the floor plane.
        """
        d = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)])
        moved = matrix(self.placement.rotation) @ d
        scale = np.hypot(moved[0], moved[1])
        if scale.size and scale.min() < math.cos(MAX_TILT):
            tilt = math.degrees(math.acos(min(float(scale.min()), 1.0)))
            raise ValueError(f"The sensor's beams leave the floor plane by up to {tilt:.0f} degrees (its mount "
                             f"{self.describe()}); a planar scan is read within {math.degrees(MAX_TILT):.0f}.")
        directions = np.unwrap(np.arctan2(moved[1], moved[0]))
        origins = np.empty((len(angles), 2))
        origins[:] = self.placement.translation[:2]
        return origins, directions, scale

    def describe(self) -> str:
        x, y, _ = self.placement.translation
        _, _, yaw = self.placement.planar
        flipped = matrix(self.placement.rotation)[2, 2] < 0
        return (f"x={x:.3g} m, y={y:.3g} m, yaw={math.degrees(yaw):.3g} deg" + (", upside down" if flipped else "")
                + f", from {self.origin}")


def parse_mount(text: str) -> tuple[str | None, Mount]:
    """``[TOPIC=]X,Y,YAW[,flipped]`` (m, m, degrees) as the topic it is for (None: every scan topic) and its mount.

    Examples
    --------
    >>> topic, mount = parse_mount("/scan_rear=-0.3,0,180,flipped")
    >>> topic, mount.describe()
    ('/scan_rear', 'x=-0.3 m, y=0 m, yaw=180 deg, upside down, from option')
    """
    topic, _, values = text.rpartition("=")
    parts = [p.strip() for p in values.split(",")]
    flipped = parts[-1].lower() in ("flipped", "upside-down", "upside_down")
    numbers = parts[:-1] if flipped else parts
    try:
        x, y, yaw = (float(v) for v in numbers)
    except ValueError:
        raise ValueError(f"A mount is [TOPIC=]X,Y,YAW[,flipped] (m, m, degrees); got {text!r}.") from None
    if not all(math.isfinite(v) for v in (x, y, yaw)):
        raise ValueError(f"A mount's X, Y and YAW must be finite; got {text!r}.")
    return topic or None, Mount.planar(x, y, math.radians(yaw), flipped)
