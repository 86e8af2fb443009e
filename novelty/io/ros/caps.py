"""The largest messages the readers accept, and where an error says the file broke them.

A recording states the sizes of what it holds: a ROS 1 bag's chunk its
uncompressed size, a message record its length (a uint32: up to 4 GB), a
``LaserScan`` its number of beams, a ``PointCloud2`` its points, fields and
steps. A 5 KB compressed bag can state 50 million beams. The readers check
every stated size against the caps below and against the bytes actually
there *before* anything is decompressed, copied or allocated, and refuse a
file beyond them with a :class:`MessageError` that names the file, the
topic, the message's number on it and the field. Memory then stays bounded
by the caps whatever the file says: a chunk is inflated to at most
:data:`MAX_CHUNK_BYTES`, a message is at most :data:`MAX_MESSAGE_BYTES`.

The caps are far above what real sensors send (a 360-degree lidar at 0.1
degrees has 3,600 beams, an Ouster OS1-128 cloud about 260,000 points of 48
bytes); a recording beyond them can be read after raising them, e.g.
``novelty.io.ros.caps.MAX_BEAMS = 10**6``.
"""

from __future__ import annotations

__all__ = ["MAX_BEAMS", "MAX_ECHOES", "MAX_POINTS", "MAX_FIELDS", "MAX_TRANSFORMS", "MAX_TF_DEPTH",
           "MAX_TF_FRAMES", "MAX_TF_SAMPLES", "MAX_WAITING_BEAMS", "MAX_NAME", "MAX_CHUNK_BYTES",
           "MAX_MESSAGE_BYTES", "MAX_HELD_BYTES", "MessageError", "TruncatedError", "Where"]

#: Beams of one ``LaserScan`` or ``MultiEchoLaserScan``.
MAX_BEAMS = 100_000
#: Echoes of one beam of a ``MultiEchoLaserScan``.
MAX_ECHOES = 32
#: Points of one ``PointCloud2`` (height x width).
MAX_POINTS = 4_000_000
#: Fields of one ``PointCloud2`` point.
MAX_FIELDS = 256
#: Transforms of one ``tf`` message.
MAX_TRANSFORMS = 10_000
#: Frames of one chain of a tf tree, from a leaf to its root (REP 105's map -> odom -> base_link -> sensor is 4;
#: a robot's URDF a few tens).
MAX_TF_DEPTH = 100
#: Frames of one tf tree.
MAX_TF_FRAMES = 10_000
#: Moving samples of one tf edge held: its last ``2 x cache`` seconds, thinned to one a ``4 x cache /
#: MAX_TF_SAMPLES`` seconds (0.004 s at the default 10 s cache: 250 samples a second, beyond odometry's usual 50).
MAX_TF_SAMPLES = 10_000
#: Beams (or points) of the scans read ahead of their turn: waiting for the poses after their time, or for
#: another sensor's topic to learn its fragments (about 97 s of a 1,081-beam laser at 40 Hz).
MAX_WAITING_BEAMS = 2**22
#: Characters of a frame's or field's name.
MAX_NAME = 4_096
#: The serialized bytes of one message (a cloud of MAX_POINTS points of 16 bytes fits).
MAX_MESSAGE_BYTES = 64 * 2**20
#: The uncompressed bytes of one ROS 1 bag chunk holding a message read (messages of other topics
#: share it: a chunk closes after its first 768 KB by default, so it holds one large image at most).
MAX_CHUNK_BYTES = 128 * 2**20
#: The bytes of ROS 1 messages inflated before their turn: each chunk is inflated once, and the messages of it
#: due after another chunk's (chunks whose times interleave) wait.
MAX_HELD_BYTES = 128 * 2**20


class MessageError(ValueError):
    """A message (or the record holding it) whose stated sizes are beyond a cap or beyond its bytes."""


class TruncatedError(MessageError):
    """A field that states more bytes than its message holds."""


class Where:
    """A message's place in its file, for its errors: ``file, topic T, message N (field): ...``."""

    __slots__ = ("path", "topic", "number")

    def __init__(self, path, topic: str, number: int):
        self.path, self.topic, self.number = path, topic, number

    def __str__(self) -> str:
        return f"{self.path}, topic {self.topic}, message {self.number}"

    def error(self, field: str, text: str) -> MessageError:
        return MessageError(f"{self} ({field}): {text}")

    def count(self, value: int, cap: int, field: str, what: str, name: str) -> int:
        """``value`` if it is at most ``cap``; else the error saying so (``name`` the cap's)."""
        if value > cap:
            raise self.error(field, f"states {value:,} {what}; at most {cap:,} are read "
                             f"(novelty.io.ros.caps.{name}).")
        return value

    def within(self, needed: int, available: int, field: str) -> None:
        """Refuse a field that reaches beyond the message's bytes (the first ``needed`` of ``available``)."""
        if needed > available:
            raise TruncatedError(f"{self} ({field}): reaches "
                                 f"byte {needed:,} of a message of {available:,} (a truncated or corrupt message).")
