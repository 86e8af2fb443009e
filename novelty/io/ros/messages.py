"""The messages a robot recording holds, as the readers of :mod:`novelty.io` return them.

One small type per kind of reading, whatever the file format: a laser scan
(:class:`LaserScan`, the fields of ROS's ``sensor_msgs/LaserScan``), one
ranger's reading (:class:`RangeReading`, ``sensor_msgs/Range``: one sonar or
infrared sensor) and a robot pose (:class:`Pose`, from odometry or a
localiser). Times are seconds (a float), lengths metres, angles radians,
counter-clockwise, in the frame of the sensor (or of the robot where the
reader knows the sensor's mounting: a CARMEN ``ROBOTLASER1`` or ``RLASER``).

References
----------
ROS ``sensor_msgs/LaserScan`` and ``sensor_msgs/Range`` message definitions
(the field names and meanings kept here); REP 103 (units and the
counter-clockwise, x-forward convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["LaserScan", "RangeReading", "Pose", "Transform", "Sweep"]


@dataclass(frozen=True, eq=False)
class LaserScan:
    """One sweep of a planar laser: ``ranges[i]`` was measured at ``angle_min + i * angle_increment``.

    Attributes
    ----------
    stamp : float
        Time of the first beam (s).
    ranges : ndarray of shape (n_beams,)
        Ranges (m) as recorded: NaN, ``inf`` and values outside
        [``range_min``, ``range_max``] keep the meanings of
        :func:`novelty.io.scans.ranges.clean_ranges`.
    angle_min, angle_increment : float
        Angle of the first beam and between beams (rad).
    range_min, range_max : float
        The sensor's valid range (m); ``range_max`` is ``inf`` when unknown.
    pose : ndarray of shape (3,) or None
        The robot's pose (x, y, heading) at the scan, when the message
        carries one (CARMEN's corrected pose).
    source : str
        The topic or message type the scan came from.
    origin : (float, float)
        The sensor's position (m) in the robot's frame, where the reader
        knows it (a CARMEN ``ROBOTLASER1``); (0, 0) otherwise.
    frame : str
        The sensor's frame (a ROS message's ``header.frame_id``), "" when unknown.
    """

    stamp: float
    ranges: np.ndarray
    angle_min: float
    angle_increment: float
    range_min: float = 0.0
    range_max: float = math.inf
    pose: np.ndarray | None = None
    source: str = ""
    origin: tuple[float, float] = (0.0, 0.0)
    frame: str = ""

    @property
    def angles(self) -> np.ndarray:
        """The angle of every beam (rad)."""
        return self.angle_min + self.angle_increment * np.arange(len(self.ranges))


@dataclass(frozen=True)
class RangeReading:
    """One reading of one ranger (a sonar, an infrared sensor): ``sensor_msgs/Range``.

    Attributes
    ----------
    stamp : float
        Time of the reading (s).
    range : float
        The range (m); ``-inf`` a detection too close to measure, ``+inf``
        no detection (REP 117, and the ``Range`` message's comments).
    sensor : str
        Which ranger: the message's frame, or its topic when the frame is empty.
    range_min, range_max : float
        The sensor's valid range (m).
    field_of_view : float
        The cone's full angle (rad).
    frame : str
        The message's frame ("" when unknown).
    """

    stamp: float
    range: float
    sensor: str
    range_min: float = 0.0
    range_max: float = math.inf
    field_of_view: float = 0.0
    frame: str = ""


@dataclass(frozen=True)
class Pose:
    """The robot's pose in the plane at a time: ``(x, y)`` in metres, ``theta`` its heading (rad).

    ``source`` says where it came from (``"ODOM"``, a topic name).
    """

    stamp: float
    x: float
    y: float
    theta: float
    source: str = ""


@dataclass(frozen=True)
class Transform:
    """Where frame ``child`` is in frame ``parent`` at a time: a translation and a rotation (tf's convention).

    A point ``p`` in ``child`` is ``R(rotation) p + translation`` in ``parent``
    (``geometry_msgs/TransformStamped``: ``header.frame_id`` the parent,
    ``child_frame_id`` the child).

    Attributes
    ----------
    stamp : float
        Time (s).
    parent, child : str
        The frames, without a leading ``/``.
    translation : tuple of 3 float
        (m).
    rotation : tuple of 4 float
        A unit quaternion (x, y, z, w).
    static : bool
        From ``/tf_static``: true at every time.
    """

    stamp: float
    parent: str
    child: str
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    static: bool = False


@dataclass(frozen=True, eq=False)
class Sweep:
    """One whole scan of the robot's surroundings, in its base frame (REP 103: x forward, y left, ccw).

    Attributes
    ----------
    time : float
        The scan's time (s): its first beam's, as ``LaserScan.stamp``.
    origins : ndarray of shape (n_beams, 2)
        Each beam's origin: the sensor's position in the base frame (m).
    angles : ndarray of shape (n_beams,)
        Each beam's direction in the base frame (rad).
    ranges : ndarray of shape (n_beams,)
        Cleaned as :func:`novelty.io.scans.ranges.clean_ranges` does (a range in m,
        ``+inf`` nothing seen, NaN no information), along the beam from its origin.
    pose : ndarray of shape (3,) or None
        The base frame's pose (x, y, yaw) in the world frame (odom or map)
        at ``time``, or None.
    frame : str
        The base frame's name (``base_link``, ...; "" when unknown, e.g. a CARMEN log).
    source : str
        Where the beams came from (topic(s), CARMEN message name).
    spread : ndarray of shape (n_beams,) or None
        Each beam's full cone angle (rad): None (or 0) for a laser, a
        sonar's field of view.
    """

    time: float
    origins: np.ndarray
    angles: np.ndarray
    ranges: np.ndarray
    pose: np.ndarray | None
    frame: str = ""
    source: str = ""
    spread: np.ndarray | None = None
