"""What the node does with each message, without rospy: read it, score and learn the scans it completes, count.

:class:`LiveScorer` is the whole of the node but its ROS shell: the messages'
bytes go in (as the subscriptions deliver them), each whole scan's novelty
comes out, scored then learned as ``novelty run`` scores and learns a
recording's scans (``score_learn_one``, the scan's time given to the detector
with ``stamps``), through an alarm policy of :mod:`novelty.alarms`. It
keeps the counts the diagnostics report (:class:`~novelty.rosnode.stats.Stats`),
and the faults it met, each said once (:attr:`LiveScorer.said`), none fatal:

- a message that cannot be read (a size beyond :mod:`novelty.io.ros.caps`, a
  truncated message, a pose that is not finite): left out, counted;
- time that jumps back on a topic (a bag played in a loop, ``/clock`` reset):
  the held scans, the moving transforms and the scanners' patterns are
  forgotten (the model is kept); with ``stamps`` the detector's clock goes on
  one typical step after the last scan it learned, as ``novelty run --passes``
  does between passes;
- a scan the detector refuses (another geometry mid-stream, which makes
  another number of sectors; a scan whose sectors its beams cannot fill):
  left out, counted, the model unchanged (every detector checks its input
  before it changes);
- a scan with beams without information (NaN): scored (those beams are left
  out of their sectors, as the readers do), counted.

Learning can be frozen and resumed, the model saved (atomically:
:func:`novelty.save`) and reset to its state at start.

Shares its name with novelty/_kernels/scoring.py: this is the live node's scorer, that the engines'
batch scoring.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..alarms import Alarm
from .reading import LiveReading, Row
from .stats import Stats

__all__ = ["LiveScorer", "Scored", "model_size"]


@dataclass(frozen=True, eq=False)
class Scored:
    """One scan scored: its time (s), novelty, alarm state (None: no policy), its input row, its cells.

    ``cells`` is, for a map, the novelty of the cells the scan hit (:meth:`HabituatingMap.cell_novelty`)
    when asked for, else None; ``arrival`` the node's clock when the scan's last message arrived.
    """

    time: float
    novelty: float
    alarm: bool | None
    row: Row
    cells: tuple | None
    arrival: float


class LiveScorer:
    """A detector scoring and learning live scans read by a :class:`~novelty.rosnode.reading.LiveReading`.

    Parameters
    ----------
    detector : NoveltyDetector
        Scores then learns each scan (``score_learn_one``); frozen, scores only.
    reading : LiveReading
    alarm : Alarm or None
    fresh : callable
        Builds the detector :meth:`reset` returns to (a new one, or the model loaded at start).
    stamps : bool, default=False
        Give the detector each scan's time (s) as its elapsed time (default: one step a scan).
    learning : bool, default=True
    """

    def __init__(self, detector, reading: LiveReading, alarm: Alarm | None, fresh: Callable[[], object], *,
                 stamps: bool = False, learning: bool = True):
        self.detector, self.reading, self.alarm, self.fresh = detector, reading, alarm, fresh
        self.stamps, self.learning = stamps, learning
        self.stats = Stats()
        self.said: list[str] = []          # the faults' messages, each kind once, for the node to log
        self._told: set[str] = set()
        self._offset = 0.0                 # added to the scans' times after time jumped back (stamps)
        self._given = None                 # the last time given to the detector
        self._steps: deque = deque(maxlen=50)

    # -------------------------------------------------------------- messages
    def take(self, topic: str, msgtype: str, data: bytes, stamp_now: float, clock: float,
             cells: bool = False) -> list[Scored]:
        """One message's bytes; the scans it completes, scored. ``stamp_now``: ROS time, ``clock``: monotonic (s)."""
        self.stats.received[topic] += 1
        try:
            msg = self.reading.decode(topic, msgtype, data, stamp_now)
        except (ValueError, KeyError) as exc:
            self.stats.faults["messages not read"] += 1
            self.say("unreadable", f"A message on {topic} could not be read, and is left out: {exc}")
            return []
        latest = _latest_stamp(msg)
        if latest is not None and not topic.endswith("tf_static") and self.reading.jumped_back(topic, latest):
            self._jumped(topic, latest)
        return self._scored(self.reading.push(topic, msg, clock), cells)

    def tick(self, clock: float, cells: bool = False) -> list[Scored]:
        """The scans whose wait is over by ``clock`` (monotonic s), scored."""
        return self._scored(self.reading.release(clock), cells)

    def _jumped(self, topic: str, stamp: float) -> None:
        dropped = self.reading.restart()
        self.stats.faults["time jumps back"] += 1
        self.say("jump", f"Time jumped back on {topic} (to {stamp:.3f} s): the held scans ({dropped}), the moving "
                  "transforms and the scanners' patterns are forgotten; the model is kept.")
        if self.stamps and self._given is not None:
            step = float(np.median(self._steps)) if self._steps else 1.0
            self._offset = self._given + step - stamp

    # -------------------------------------------------------------- scoring
    def _scored(self, rows: list[Row], cells: bool) -> list[Scored]:
        self.stats.skipped.update(self.reading.skipped)
        self.reading.skipped.clear()
        for problem in self.reading.problems:
            self.say("unreadable scan", problem)
        self.reading.problems.clear()
        out = []
        for row in rows:
            scored = self._score(row, cells)
            if scored is not None:
                out.append(scored)
        return out

    def _score(self, row: Row, cells: bool) -> Scored | None:
        det = self.detector
        try:
            hit = det.cell_novelty(row.x) if cells and hasattr(det, "cell_novelty") and self._fitted() else None
            if self.learning:
                novelty = det.score_learn_one(row.x, self._time(row.time))
            else:
                novelty = det.score_one(row.x)
        except ValueError as exc:   # checked before anything changes: the model is as it was
            self.stats.skipped["refused by the detector"] += 1
            self.say("refused", f"A scan at {row.time:.3f} s was refused by the detector and left out: {exc}")
            return None
        if np.isnan(row.ranges).any():
            self.stats.faults["scans with beams without information (NaN)"] += 1
            self.say("nan", f"The scan at {row.time:.3f} s has beams without information (NaN): they are left out "
                      "of their sectors, as the readers leave them out.")
        alarm = None if self.alarm is None else bool(self.alarm.update(novelty))
        self.stats.scored += 1
        return Scored(row.time, float(novelty), alarm, row, hit, row.arrival)

    def _time(self, stamp: float) -> float | None:
        if not self.stamps:
            return None
        t = stamp + self._offset
        if self._given is not None and t > self._given:
            self._steps.append(t - self._given)
        if self._given is not None and t < self._given:   # a scan older than the last learned: no time passed
            t = self._given
        self._given = t
        return t

    def _fitted(self) -> bool:
        return hasattr(self.detector, "n_features_in_")

    def say(self, kind, text: str) -> None:
        """Queue ``text`` for the node's log, the first time a fault of ``kind`` happens."""
        if kind not in self._told:
            self._told.add(kind)
            self.said.append(text)

    # -------------------------------------------------------------- the model
    def set_learning(self, on: bool) -> None:
        self.learning = bool(on)

    def reset(self) -> None:
        """Back to the model at start (a new detector, or the model loaded), the alarm cleared."""
        self.detector = self.fresh()
        if self.alarm is not None:
            self.alarm.reset()
        self._given, self._offset = None, 0.0
        self._steps.clear()

    def save(self, path: str) -> None:
        """Save the model to ``path``, whole or not at all (:func:`novelty.persistence.save`)."""
        self.detector.save(path)


def _latest_stamp(msg) -> float | None:
    if isinstance(msg, list):
        return max((t.stamp for t in msg), default=None)
    if isinstance(msg, tuple):
        return msg[0]
    return getattr(msg, "stamp", None)


def model_size(detector) -> int:
    """The values the detector has learned: the sizes of its learned arrays (attributes ending in ``_``)."""
    seen, total, stack = set(), 0, [detector]
    while stack:
        obj = stack.pop()
        if id(obj) in seen or not hasattr(obj, "__dict__"):
            continue
        seen.add(id(obj))
        for name, value in vars(obj).items():
            if isinstance(value, np.ndarray) and name.endswith("_") and not name.startswith("_"):
                total += value.size
            elif type(value).__module__.startswith("novelty") and not isinstance(value, type):
                stack.append(value)
            elif isinstance(value, (list, tuple)) and name.endswith("_"):
                stack.extend(v for v in value if type(v).__module__.startswith("novelty"))
    return total

