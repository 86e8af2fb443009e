"""CARMEN logs: laser scans and odometry, a line at a time, plain or gzipped.

A CARMEN log is text, one message a line, its fields separated by spaces;
``#`` starts a comment line. The fields of the messages read here, as the
CARMEN logger writes them in the header of every log (and as the Radish
data sets' README describes them):

- ``FLASER n r_1 .. r_n x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname logger_timestamp``:
  a front laser scan of ``n`` ranges (m), the robot's (corrected) pose and
  its odometry pose at the scan. The message does not say the beams'
  angles: a 180-degree laser is assumed, the first beam at the robot's
  right, the last at its left (``fov`` changes the spread).
- ``RLASER``: the same for a rear laser; its beams point backwards (their
  angles here are the robot's: the first beam at ``pi - fov / 2``).
- ``ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range accuracy
  remission_mode n r_1 .. r_n m v_1 .. v_m laser_x laser_y laser_theta robot_x robot_y robot_theta
  tv rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp ipc_hostname logger_timestamp``:
  a laser scan that states its geometry; its angles are turned into the
  robot's frame by the laser's heading relative to the robot's, and its
  origin is the laser's position in the robot's frame (both poses are the
  world's: the laser's offset is turned by the robot's heading).
- ``ODOM x y theta tv rv accel ipc_timestamp ipc_hostname logger_timestamp``: odometry.

A message's time is its ``ipc_timestamp`` (s). Other messages (``PARAM``,
``SYNC``, ``NEFF``, ``TRUEPOS``, raw lasers, ...) are skipped and counted in
:attr:`CarmenLog.skipped`. Reading is lazy: a line is read when the
iteration asks for the next message, so stopping early reads nothing more,
and memory holds one line (at most :data:`MAX_LINE` characters).

References
----------
Montemerlo, M., Roy, N. & Thrun, S. (2003). Perspectives on standardization
in mobile robot programming: the Carnegie Mellon Navigation (CARMEN)
toolkit. IROS 2003. The log format: the header the CARMEN logger writes
(``# message_name [message contents] ipc_timestamp ipc_hostname logger_timestamp``).
Howard, A. & Roy, N. (2003). The Robotics Data Set Repository (Radish).
"""

from __future__ import annotations

import gzip
import math
import re
from collections import Counter
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from ..tables.data_files import is_float
from ..ros.messages import LaserScan, Pose

__all__ = ["CarmenLog", "CarmenError", "read_carmen", "CARMEN_MESSAGES", "MAX_LINE"]

#: The messages this reader turns into :class:`LaserScan` or :class:`Pose`.
CARMEN_MESSAGES = ("FLASER", "RLASER", "ROBOTLASER1", "ODOM")
#: The longest line read (characters): a 1,081-beam laser with remissions is about 20,000.
MAX_LINE = 1_000_000

_NAME = re.compile(r"[A-Z][A-Z0-9_]*\Z")
_POSE_FIELDS = ("x", "y", "theta", "odom_x", "odom_y", "odom_theta")


class CarmenError(ValueError):
    """A file that is not a CARMEN log, or a line of one that cannot be read."""


class CarmenLog:
    """The messages of a CARMEN log, read lazily.

    Parameters
    ----------
    path : str or Path
        The log: text, or gzip (recognised by its first bytes, whatever its name).
    messages : sequence of str, default=CARMEN_MESSAGES
        The message types to read; every other line is skipped and counted.
    fov : float, default=pi
        The field of view (rad) of ``FLASER``/``RLASER`` scans, whose
        messages do not state it.

    Attributes
    ----------
    skipped : Counter
        How many lines of each other message type the reading has passed so far.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "tiny.log")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("# a comment\\nPARAM robot_use_laser on nohost 0\\n"
    ...                  "FLASER 3 1.0 2.0 3.0 0.5 0.0 0.0 0.5 0.0 0.0 12.5 host 12.5\\n")
    >>> log = CarmenLog(path)
    >>> [(type(m).__name__, m.stamp, m.ranges.tolist()) for m in log]
    [('LaserScan', 12.5, [1.0, 2.0, 3.0])]
    >>> dict(log.skipped)
    {'PARAM': 1}
    """

    def __init__(self, path, messages: Sequence[str] = CARMEN_MESSAGES, fov: float = math.pi):
        unknown = sorted(set(messages) - set(CARMEN_MESSAGES))
        if unknown:
            raise ValueError(f"CARMEN messages {unknown} are not read here; choose among "
                             f"{', '.join(CARMEN_MESSAGES)}.")
        if not 0 < fov <= 2 * math.pi:
            raise ValueError(f"fov must be in (0, 2 pi] radians; got {fov!r}.")
        self.path = Path(path)
        self.messages = tuple(messages)
        self.fov = float(fov)
        self.skipped: Counter = Counter()

    def __iter__(self) -> Iterator[LaserScan | Pose]:
        self.skipped = Counter()
        seen_message = False
        with _open_text(self.path) as fh:
            for number, line in _lines(fh, self.path):
                tokens = line.split()
                if not tokens or tokens[0].startswith("#"):
                    continue
                name = tokens[0]
                if not _NAME.match(name):
                    what = "not a CARMEN log" if not seen_message else "a corrupt line"
                    raise CarmenError(f"{self.path}, line {number}: {what}: expected a message "
                                      f"name in capitals (FLASER, ODOM, ...); got {name[:40]!r}.")
                seen_message = True
                if name not in self.messages:
                    self.skipped[name] += 1
                    continue
                yield _PARSERS[name](self, tokens, _Where(self.path, number, name))


def read_carmen(path, messages: Sequence[str] = CARMEN_MESSAGES, fov: float = math.pi):
    """The messages of a CARMEN log, one at a time (see :class:`CarmenLog`)."""
    return iter(CarmenLog(path, messages, fov))


# ------------------------------------------------------------------ reading
def _open_text(path: Path):
    with open(path, "rb") as fh:
        magic = fh.read(2)
    if magic == b"\x1f\x8b":
        return gzip.open(path, "rt", encoding="ascii", newline="")
    return open(path, encoding="ascii", newline="")


def _lines(fh, path: Path):
    number = 0
    while True:
        try:
            line = fh.readline(MAX_LINE)
        except UnicodeDecodeError:
            raise CarmenError(f"{path}, line {number + 1}: not a CARMEN log (not ASCII text).") from None
        except (EOFError, gzip.BadGzipFile, OSError) as exc:
            raise CarmenError(f"{path}: the gzip stream is truncated or corrupt after line {number} "
                              f"({exc}).") from None
        if not line:
            return
        number += 1
        if len(line) >= MAX_LINE and not line.endswith("\n"):
            raise CarmenError(f"{path}, line {number}: longer than {MAX_LINE} characters; "
                              "not a CARMEN log line.")
        yield number, line


class _Where:
    """Where a message is, for its error messages."""

    def __init__(self, path: Path, number: int, name: str):
        self.path, self.number, self.name = path, number, name

    def error(self, text: str) -> CarmenError:
        return CarmenError(f"{self.path}, line {self.number} ({self.name}): {text}")

    def numbers(self, tokens: Sequence[str], start: int, count: int, what: str) -> np.ndarray:
        """``count`` numbers from ``tokens[start]``; a short or non-numeric line is an error."""
        if len(tokens) < start + count:
            raise self.error(f"{len(tokens) - 1} fields; {what} needs {start + count - 1} "
                             "(truncated line?).")
        try:
            return np.array(tokens[start:start + count], dtype=np.float64)
        except ValueError:
            bad = next(t for t in tokens[start:start + count] if not is_float(t))
            raise self.error(f"{what}: {bad[:40]!r} is not a number.") from None

    def count(self, tokens: Sequence[str], at: int, what: str) -> int:
        n = self.numbers(tokens, at, 1, what)[0]
        # a count is a whole number no larger than a line could hold (inf and nan are neither)
        if not (math.isfinite(n) and n == int(n) and 0 <= n <= MAX_LINE):
            raise self.error(f"{what} is {tokens[at]!r}; expected a count of readings.")
        return int(n)

    def finite(self, values: np.ndarray, names: Sequence[str]) -> np.ndarray:
        """``values`` if all are finite; else the error naming the first that is not."""
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise self.error(f"{names[bad[0]]} is {values[bad[0]]}; a pose must be finite.")
        return values


# ------------------------------------------------------------------ messages
def _old_laser(log: CarmenLog, tokens, where: _Where) -> LaserScan:
    n = where.count(tokens, 1, "the number of readings")
    if n < 2:
        raise where.error(f"{n} readings; a scan needs at least 2.")
    ranges = where.numbers(tokens, 2, n, "the ranges")
    tail = where.numbers(tokens, 2 + n, 7, "the poses and the timestamp")
    where.finite(tail, _POSE_FIELDS + ("ipc_timestamp",))
    facing = math.pi if where.name == "RLASER" else 0.0
    return LaserScan(stamp=float(tail[6]), ranges=ranges, angle_min=facing - log.fov / 2,
                     angle_increment=log.fov / (n - 1), pose=tail[:3], source=where.name)


def _robot_laser(log: CarmenLog, tokens, where: _Where) -> LaserScan:
    head = where.numbers(tokens, 1, 8, "the laser's configuration")
    start_angle, resolution, max_range = head[1], head[3], head[4]
    n = where.count(tokens, 8, "the number of readings")
    ranges = where.numbers(tokens, 9, n, "the ranges")
    m = where.count(tokens, 9 + n, "the number of remissions")
    tail = where.numbers(tokens, 10 + n + m, 12, "the poses, velocities and timestamp")
    where.finite(tail[:6], ("laser_x", "laser_y", "laser_theta", "robot_x", "robot_y", "robot_theta"))
    laser_pose, robot_pose = tail[:3], tail[3:6]
    # both poses are in the world frame: the laser's offset, turned into the robot's frame
    dx, dy = laser_pose[0] - robot_pose[0], laser_pose[1] - robot_pose[1]
    c, s = math.cos(robot_pose[2]), math.sin(robot_pose[2])
    return LaserScan(stamp=float(tail[11]), ranges=ranges,
                     angle_min=float(start_angle + laser_pose[2] - robot_pose[2]),
                     angle_increment=float(resolution), range_max=float(max_range),
                     pose=robot_pose, source=where.name, origin=(float(c * dx + s * dy), float(c * dy - s * dx)))


def _odometry(log: CarmenLog, tokens, where: _Where) -> Pose:
    values = where.numbers(tokens, 1, 7, "the pose, velocities and timestamp")
    where.finite(values[[0, 1, 2, 6]], ("x", "y", "theta", "ipc_timestamp"))
    return Pose(stamp=float(values[6]), x=float(values[0]), y=float(values[1]), theta=float(values[2]),
                source=where.name)


_PARSERS = {"FLASER": _old_laser, "RLASER": _old_laser, "ROBOTLASER1": _robot_laser, "ODOM": _odometry}
