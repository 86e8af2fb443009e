"""Sonar rings from ``Range`` messages: one reading of every sonar, gathered by time.

The paper's novelty filter takes a ring of ranges, one a sensor around the
robot (16 sonars, Marsland et al. 2000, section 4.1); a robot's recording
holds one ``sensor_msgs/Range`` message a sonar. :func:`sonar_rings` gathers
them into rings in the order of the sonars' mounting angles, each reading
cleaned by the ROS conventions first (:func:`.scans.clean_ranges`: NaN and
out-of-range values become ``+inf`` here, nothing seen).

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
of an environment using habituation. Proc. SAB 2000, section 4.1.
ROS ``sensor_msgs/Range`` message definition and REP 117 (Bohren, 2012).
"""

from __future__ import annotations

import re
from typing import Iterable, Iterator, Mapping, Sequence

import numpy as np

from ..ros.messages import RangeReading
from .ranges import clean_ranges

__all__ = ["sonar_rings"]


def sonar_rings(readings: Iterable[RangeReading], sensors: Sequence[str] | Mapping[str, float] | None = None,
                max_span: float | None = None) -> Iterator[tuple[float, np.ndarray]]:
    """Gather one reading of every sonar into a ring: ``(time, ranges)``, in mounting order.

    A ring is complete when every sensor has reported since the last ring;
    its time is its newest reading's. A sensor reporting twice before the
    ring completes keeps its newer reading.

    Parameters
    ----------
    readings : iterable of RangeReading
        In time order.
    sensors : sequence of str, or dict of str to float, optional
        The sensors in mounting order, or each sensor's mounting angle (rad;
        the ring runs counter-clockwise from the smallest). Default: the
        sensors met before the first repeat, in natural name order
        (``sonar2`` before ``sonar10``): ``Range`` messages do not carry
        their mounting angle, so give it where the names do not follow it.
    max_span : float, optional
        Seconds: a reading older than this before the newest one of the
        ring is dropped (its sensor reports again before the ring completes).

    Examples
    --------
    >>> rs = [RangeReading(0.0, 1.0, "s1"), RangeReading(0.1, 2.0, "s0"),
    ...       RangeReading(0.2, float("inf"), "s1"), RangeReading(0.3, 0.5, "s0")]
    >>> [(t, ring.tolist()) for t, ring in sonar_rings(rs)]
    [(0.1, [2.0, 1.0]), (0.3, [0.5, inf])]
    """
    it = iter(readings)
    order = _sensor_order(sensors) if sensors is not None else None
    pending: list[RangeReading] = []
    if order is None:
        order, pending = _discover_sensors(it)
    position = {name: i for i, name in enumerate(order)}
    ring: dict[str, RangeReading] = {}
    for reading in _chain(pending, it):
        if reading.sensor not in position:
            raise ValueError(f"A reading of sensor {reading.sensor!r}, not one of the ring's "
                             f"{list(order)}.")
        ring[reading.sensor] = reading
        if max_span is not None:
            ring = {k: v for k, v in ring.items() if reading.stamp - v.stamp <= max_span}
        if len(ring) == len(order):
            values = [clean_ranges([ring[s].range], ring[s].range_min, ring[s].range_max)[0]
                      for s in order]
            yield max(v.stamp for v in ring.values()), np.where(np.isnan(values), np.inf, values)
            ring = {}


def _chain(first, rest):
    yield from first
    yield from rest


def _sensor_order(sensors) -> list[str]:
    if isinstance(sensors, Mapping):
        return [name for name, _ in sorted(sensors.items(), key=lambda item: (float(item[1]), item[0]))]
    order = [str(s) for s in sensors]
    if not order or len(set(order)) != len(order):
        raise ValueError(f"sensors must name each sensor once; got {order!r}.")
    return order


def _discover_sensors(it) -> tuple[list[str], list[RangeReading]]:
    seen: list[RangeReading] = []
    names: set[str] = set()
    for reading in it:
        if reading.sensor in names:
            return sorted(names, key=_natural), seen + [reading]
        names.add(reading.sensor)
        seen.append(reading)
    return sorted(names, key=_natural), seen


def _natural(name: str):
    # decimal digits only: int() refuses the other "digits" \d and str.isdigit() take (superscripts)
    return [(0, int(part), "") if part.isdecimal() else (1, 0, part) for part in re.split(r"(\d+)", name)]
