"""Whole scans from fragments: a scanner that publishes each revolution as several messages, put together.

Some drivers split a revolution into messages of a few tens of degrees
each (a safety laser: a 275-degree revolution as 6 messages). Reduced one by
one, each fragment would make a ring of slices of one small piece, and a
recording of 87 revolutions would read as 522 scans. :class:`Assembler`
finds the pattern in a topic's first messages and puts each revolution
together before anything is reduced:

- **detected**: fragments are messages of one frame whose spans tile a
  larger span of at most one turn: the ``P`` geometries (first angle,
  beams, spacing) of a topic's first :data:`LEARN` messages (or of those of
  its first :data:`LEARN_SECONDS`, when it sends fewer), each starting where
  another ends (within half a beam's spacing, modulo a whole turn), in one
  chain. A revolution starts at the fragment that no other continues (or,
  all round, at the first from -pi, within half a beam); one geometry
  (every message alike) is a scanner of whole scans, passed through as they
  are, and so are geometries that do not tile a revolution;
- **stated**: ``fragments=N`` says the scanner sends N messages a
  revolution (the cycle must have that length); ``fragments=1`` turns
  assembly off;
- **incomplete revolutions** (a fragment missing, out of order, of another
  geometry, or later than one and a half revolutions' time after the
  revolution's first) are left out and counted, never reduced as if whole;
  the recording's first revolution, begun before it, is one of them.

An assembled scan's time is its first fragment's (its first beam's, as a
``LaserScan``'s stamp); its ranges are each fragment's cleaned by that
fragment's own valid range (:func:`novelty.io.scans.ranges.clean_ranges`).
"""

from __future__ import annotations

import math
from typing import Iterator

import numpy as np

from ..ros.messages import LaserScan
from .ranges import clean_ranges

__all__ = ["Assembler", "LEARN", "LEARN_SECONDS"]

#: Messages looked at to find a topic's pattern of fragments.
LEARN = 100
#: Seconds of the recording after a topic's first message held for learning by which its pattern is decided
#: from the messages held so far, however few (a topic that stops early holds back no other's scans longer).
LEARN_SECONDS = 10.0


class Assembler:
    """Whole scans from one topic's messages (see the module docstring).

    Parameters
    ----------
    fragments : "auto" or int, default="auto"
        Detect the fragments a revolution, or the number stated (1: no assembly).
    topic : str
        For the messages of errors and notes.

    Attributes
    ----------
    messages, scans, incomplete : int
        Messages read, whole scans made, revolutions left out as incomplete.
    per_revolution : int or None
        Fragments a revolution, once known.
    """

    def __init__(self, fragments="auto", topic: str = ""):
        if fragments != "auto" and not (isinstance(fragments, int) and not isinstance(fragments, bool)
                                        and fragments >= 1):
            raise ValueError(f"fragments must be 'auto' or a count >= 1 (1: no assembly); got {fragments!r}.")
        self.fragments, self.topic = fragments, topic
        self.messages = self.scans = self.incomplete = 0
        self.per_revolution: int | None = 1 if fragments == 1 else None
        self._learning: list[LaserScan] = []
        self._slots: dict[tuple, int] = {}
        self._start = 0
        self._period = math.inf
        self._current: list[LaserScan] = []
        self._orphans = False   # fragments seen of a revolution whose start was not (counted when it ends)
        self._tail = False      # fragments seen of a revolution already counted as incomplete

    def push(self, scan: LaserScan) -> Iterator[LaserScan]:
        """Take one message; yield the whole scans it completes."""
        self.messages += 1
        if self.per_revolution == 1:
            self.scans += 1
            yield scan
            return
        if self.per_revolution is None:
            self._learning.append(scan)
            if len(self._learning) < LEARN:
                return
            yield from self._replay()
            return
        yield from self._assemble(scan)

    def flush(self) -> Iterator[LaserScan]:
        """The whole scans of the messages still held, when the topic has no more."""
        yield from self.settle()
        self._drop()

    def settle(self) -> Iterator[LaserScan]:
        """Decide the pattern from the messages held so far, however few; the whole scans they make."""
        if self.per_revolution is None and self._learning:
            yield from self._replay()

    @property
    def holding_since(self) -> float:
        """The time of the oldest message held while the pattern is learned (``inf`` when none is)."""
        return self._learning[0].stamp if self._learning else math.inf

    def _replay(self) -> Iterator[LaserScan]:
        """Learn the pattern from the messages held, then pass them through it."""
        self._learn()
        learned, self._learning = self._learning, []
        for scan in learned:
            if self.per_revolution == 1:
                self.scans += 1
                yield scan
            else:
                yield from self._assemble(scan)

    # -------------------------------------------------------------- the pattern
    def _learn(self) -> None:
        keys = [_key(s) for s in self._learning]
        first = {}
        for k, s in zip(keys, self._learning):
            first.setdefault(k, s)
        order = _tiling(list(first.values())) if len(first) > 1 else None
        if order is None:
            if self.fragments not in ("auto", 1):
                raise ValueError(f"{self.topic}: {self.fragments} fragments a revolution were stated, but its first "
                                 f"{len(keys)} messages {'are alike' if len(first) == 1 else 'do not tile a revolution'} "
                                 "(fragments start, one after another, where the one before ended).")
            self.per_revolution = 1   # whole scans (or several geometries that are not one revolution's pieces)
            return
        period = len(order)
        if self.fragments not in ("auto", period):
            raise ValueError(f"{self.topic}: {self.fragments} fragments a revolution were stated, but its first "
                             f"messages tile a revolution in {period}.")
        self.per_revolution = period
        self._slots = {_key(s): i for i, s in enumerate(order)}
        self._start = 0
        starts = np.array([s.stamp for s, k in zip(self._learning, keys) if self._slots[k] == 0])
        self._period = float(np.median(np.diff(starts))) if len(starts) > 1 else math.inf

    def _assemble(self, scan: LaserScan) -> Iterator[LaserScan]:
        slot = self._slots.get(_key(scan))
        if slot == self._start:
            self._drop()
            self._current = [scan]
        elif slot is not None and self._current and slot == (self._slot_of(self._current[-1]) + 1) % \
                self.per_revolution and scan.stamp - self._current[0].stamp <= 1.5 * self._period:
            self._current.append(scan)
        else:   # out of order, of a geometry outside the cycle, too late, or before any revolution's start
            if self._current:
                self._drop()
                self._tail = True      # the rest of this revolution: left out, already counted
            elif not self._tail:
                self._orphans = True   # a revolution whose start was not seen: counted when it ends
            return
        if len(self._current) == self.per_revolution:
            whole, self._current = _joined(self._current), []
            self.scans += 1
            yield whole

    def _slot_of(self, scan: LaserScan) -> int:
        return self._slots[_key(scan)]

    def _drop(self) -> None:
        """Leave out the revolution under way, or the fragments of one whose start was not seen, counting it once."""
        if self._current or self._orphans:
            self.incomplete += 1
        self._current, self._orphans, self._tail = [], False, False


def _key(scan: LaserScan) -> tuple:
    return (scan.frame, round(scan.angle_min, 6), len(scan.ranges), round(scan.angle_increment, 9))


def _gap(a: LaserScan, b: LaserScan) -> float:
    """How far (rad, modulo a whole turn) ``b`` starts from where ``a`` ends."""
    end = a.angle_min + a.angle_increment * len(a.ranges)
    return (b.angle_min - end + math.pi) % (2 * math.pi) - math.pi


def _tiling(scans: list[LaserScan]) -> list[LaserScan] | None:
    """The geometries in the order they tile a revolution, from its first; None if they do not tile one.

    They tile one when they share a frame and a spacing and each starts where
    exactly one other ends (within half a beam's spacing, modulo a whole
    turn), in one chain through them all spanning at most one turn: open (a
    partial revolution, begun by the one no other continues) or closed (all
    round, begun by the one whose first angle is the first from -pi, within
    half a beam).
    """
    inc = scans[0].angle_increment
    if len({s.frame for s in scans}) != 1 or any(not math.isclose(s.angle_increment, inc, rel_tol=1e-6) for s in scans):
        return None
    after = {}
    for i, a in enumerate(scans):
        nxt = [j for j, b in enumerate(scans) if j != i and abs(_gap(a, b)) <= abs(inc) / 2]
        if len(nxt) > 1:
            return None
        if nxt:
            after[i] = nxt[0]
    heads = set(range(len(scans))) - set(after.values())
    if len(heads) > 1:
        return None
    # all round: the revolution starts at -pi, within half a beam (a driver's float32(-pi) lies a hair below it)
    first = heads.pop() if heads else int(np.argmin([(s.angle_min + math.pi + abs(inc) / 2) % (2 * math.pi)
                                                     for s in scans]))
    chain = [first]
    while chain[-1] in after and after[chain[-1]] != first:
        chain.append(after[chain[-1]])
    span = abs(inc) * sum(len(scans[i].ranges) for i in chain)
    if len(chain) != len(scans) or span > 2 * math.pi + abs(inc) / 2:   # more than one turn is no revolution
        return None
    return [scans[i] for i in chain]


def _joined(scans: list[LaserScan]) -> LaserScan:
    first = scans[0]
    ranges = np.concatenate([clean_ranges(s.ranges, s.range_min, s.range_max) for s in scans])
    return LaserScan(first.stamp, ranges, first.angle_min, first.angle_increment, 0.0, math.inf,
                     source=first.source, frame=first.frame)
