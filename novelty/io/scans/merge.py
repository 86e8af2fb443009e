"""Several sensors' sweeps made one: the beams of sweeps taken within a stated time of each other, together.

A robot with two lasers (front and rear, left and right) sees its
surroundings through both: their sweeps, each already in the robot's base
frame through its mount (:mod:`.mounts`), are merged into one sweep whose
ring is the robot's whole view, as ROS's laser mergers merge scans in a
common frame before anything reads them. :class:`Merger` keeps each
sensor's latest sweep; when every sensor has one and the earliest is within
``tolerance`` seconds of the latest, they are merged and the next round
begins. A sweep older than ``tolerance`` before the newest is dropped (its
sensor's next one will do) and counted. The merged sweep's time (and pose)
is its earliest part's; the robot's motion between the parts is not undone.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..ros.messages import Sweep

__all__ = ["Merger", "merged"]


class Merger:
    """One sweep from each of ``sources``, taken within ``tolerance`` seconds, made one (see the module docstring)."""

    def __init__(self, sources: Sequence[str], tolerance: float = 0.1):
        if not tolerance >= 0:
            raise ValueError(f"tolerance must be a number of seconds >= 0; got {tolerance!r}.")
        self.sources, self.tolerance = list(sources), float(tolerance)
        self.latest: dict[str, Sweep] = {}
        self.merged = self.dropped = 0
        self._geometry: dict = {}

    def push(self, source: str, sweep: Sweep) -> Sweep | None:
        """Take one sensor's sweep; the merged sweep when this completes a round, else None."""
        if source in self.latest:
            self.dropped += 1   # its sensor swept again before the others: the newer one is kept
        self.latest[source] = sweep
        newest = max(s.time for s in self.latest.values())
        stale = [k for k, s in self.latest.items() if newest - s.time > self.tolerance]
        for k in stale:
            del self.latest[k]
            self.dropped += 1
        if len(self.latest) < len(self.sources):
            return None
        parts, self.latest = [self.latest[k] for k in self.sources], {}
        self.merged += 1
        return merged(parts, self._geometry)


def merged(parts: Sequence[Sweep], geometry: dict | None = None) -> Sweep:
    """The sweeps' beams as one sweep: the earliest part's time, pose and frame.

    ``geometry`` (a dict kept between calls) keeps the joined origins and
    angles while the parts' own arrays are the same ones (a reader shares
    them between the sweeps of a sensor), read-only, so that the rings of
    the merged sweeps reuse what they worked out for them.
    """
    first = min(parts, key=lambda s: s.time)
    spread = None
    if any(p.spread is not None for p in parts):
        spread = np.concatenate([np.zeros(len(p.angles)) if p.spread is None else p.spread for p in parts])
    key = tuple((id(p.origins), id(p.angles)) for p in parts)
    shared = geometry is not None and all(not p.origins.flags.writeable and not p.angles.flags.writeable
                                          for p in parts)
    if shared and geometry.get("key") == key:
        origins, angles = geometry["arrays"]
    else:
        origins, angles = np.concatenate([p.origins for p in parts]), np.concatenate([p.angles for p in parts])
        if shared:
            origins.flags.writeable = angles.flags.writeable = False
            # the parts are held too, so that their ids stay theirs while the key is kept
            geometry.update(key=key, arrays=(origins, angles), parts=[(p.origins, p.angles) for p in parts])
    return Sweep(first.time, origins, angles, np.concatenate([p.ranges for p in parts]), first.pose, first.frame,
                 ",".join(p.source for p in parts), spread)
