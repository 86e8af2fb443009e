"""The node's counts for its diagnostics: scans received, scored, skipped and why, drops, latency, stops.

Pure bookkeeping, without rospy: :class:`Stats` is filled by the scorer and
the node's queue, and read once a second into a
``diagnostic_msgs/DiagnosticStatus`` (:meth:`Stats.values`, :meth:`Stats.level`).
Latency is the time from a scan's (last) message arriving to its novelty
being published, over the last :data:`WINDOW` scans; its percentiles are
numpy's (linear interpolation).

Shares its name with novelty/bench/stats/: this is the live node's counts and latencies, that the
benchmark's statistics.
"""

from __future__ import annotations

from collections import Counter, deque

import numpy as np

__all__ = ["Stats", "WINDOW", "OK", "WARN", "ERROR"]

#: Scans whose latencies the percentiles are taken over.
WINDOW = 1000
#: ``diagnostic_msgs/DiagnosticStatus`` levels.
OK, WARN, ERROR = 0, 1, 2


class Stats:
    """Counts since the node started (see the module docstring).

    Attributes
    ----------
    received : Counter
        Messages received, by topic.
    scored : int
        Scans scored.
    skipped : Counter
        Whole scans left out, by reason.
    faults : Counter
        What went wrong and was survived, by kind (messages not read, time jumps, scans stopped, ...).
    dropped : int
        Scans dropped from a full queue (the node scored more slowly than they came).
    """

    def __init__(self):
        self.received: Counter = Counter()
        self.scored = 0
        self.skipped: Counter = Counter()
        self.faults: Counter = Counter()
        self.dropped = 0
        self.latencies: deque = deque(maxlen=WINDOW)
        self.scans = 0                       # scan messages arrived (counted as they arrive, before the queue)
        self.first_scan: float | None = None
        self.last_scan: float | None = None
        self.stopped = False

    def scan_arrived(self, clock: float) -> str | None:
        """Note a scan message at ``clock`` (s); the line to log when it ends a stop."""
        self.scans += 1
        self.first_scan = clock if self.first_scan is None else self.first_scan
        was, self.last_scan = self.last_scan, clock
        if self.stopped:
            self.stopped = False
            return f"Scans resumed after {clock - was:.1f} s without any."
        return None

    def check_stopped(self, clock: float, after: float) -> str | None:
        """The line to log when no scan has come for ``after`` seconds (once a stop)."""
        if self.stopped or self.last_scan is None or clock - self.last_scan < after:
            return None
        self.stopped = True
        self.faults["scans stopped"] += 1
        return f"No scan for {clock - self.last_scan:.1f} s: the scans stopped (the model is kept; scoring resumes " \
               "with the next scan)."

    def published(self, latency: float) -> None:
        """Note one scan's latency (s) from arrival to publication."""
        self.latencies.append(latency)

    def latency_ms(self) -> tuple[float, float] | None:
        """The median and 99th percentile of the recent latencies (ms), or None before any."""
        if not self.latencies:
            return None
        p50, p99 = np.percentile(np.fromiter(self.latencies, float), [50, 99]) * 1e3
        return float(p50), float(p99)

    def level(self) -> tuple[int, str]:
        """The diagnostics' level and summary: OK, or WARN with what is wrong now."""
        if self.last_scan is None:
            return WARN, "waiting for scans"
        if self.stopped:
            return WARN, "scans stopped"
        return OK, f"{self.scored} scans scored"

    def summary(self) -> str:
        """One line of what the node did: scan messages arrived (over how long), scans scored, skipped, dropped,
        and the latencies."""
        latency = self.latency_ms()
        span = 0.0 if self.first_scan is None else self.last_scan - self.first_scan
        return (f"{self.scans} scan messages in {span:.2f} s, {self.scored} scans scored, "
                f"{sum(self.skipped.values())} skipped, {self.dropped} dropped from a full queue"
                + ("" if latency is None else f"; latency median {latency[0]:.2f} ms, 99th percentile "
                                              f"{latency[1]:.2f} ms"))

    def values(self) -> list[tuple[str, str]]:
        """Key-value pairs for ``DiagnosticStatus.values``: the counts, the latencies."""
        out = [(f"messages received on {t}", str(n)) for t, n in sorted(self.received.items())]
        out.append(("scans scored", str(self.scored)))
        out += [(f"scans skipped: {why}", str(n)) for why, n in sorted(self.skipped.items())]
        out.append(("scans dropped from a full queue", str(self.dropped)))
        out += [(kind, str(n)) for kind, n in sorted(self.faults.items())]
        latency = self.latency_ms()
        if latency is not None:
            out += [("latency median (ms)", f"{latency[0]:.2f}"), ("latency 99th percentile (ms)", f"{latency[1]:.2f}")]
        return out
