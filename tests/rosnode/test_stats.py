"""The node's counts: stops and their ends said once each, latency percentiles, the diagnostics' values."""

import numpy as np

from novelty.rosnode.stats import OK, WARN, WINDOW, Stats


def test_a_stop_is_said_once_and_its_end_once():
    stats = Stats()
    assert stats.level() == (WARN, "waiting for scans")
    assert stats.scan_arrived(10.0) is None
    assert stats.check_stopped(11.9, after=2.0) is None
    line = stats.check_stopped(12.5, after=2.0)
    assert line.startswith("No scan for 2.5 s") and stats.check_stopped(13.0, after=2.0) is None
    assert stats.level() == (WARN, "scans stopped") and stats.faults["scans stopped"] == 1
    assert stats.scan_arrived(14.0) == "Scans resumed after 4.0 s without any."
    assert stats.scan_arrived(14.1) is None and stats.level() == (OK, "0 scans scored")


def test_the_latency_percentiles_are_numpys_over_the_last_scans():
    stats = Stats()
    assert stats.latency_ms() is None
    for v in range(WINDOW + 100):   # the first 100 fall out of the window
        stats.published(v / 1000)
    window = np.arange(100, WINDOW + 100) / 1000
    assert stats.latency_ms() == tuple(np.percentile(window, [50, 99]) * 1e3)
    # the median of 100 ... 1099 ms is 599.5 ms; the 99th percentile 100 + 0.99 * 999 = 1089.01 ms
    np.testing.assert_allclose(stats.latency_ms(), (599.5, 1089.01), rtol=1e-12)


def test_the_values_name_every_count():
    stats = Stats()
    stats.received["/scan"] += 3
    stats.received["/tf"] += 7
    stats.scored = 2
    stats.skipped["no pose at its time"] += 1
    stats.dropped = 4
    stats.faults["time jumps back"] += 1
    stats.published(0.002)
    assert stats.values() == [
        ("messages received on /scan", "3"), ("messages received on /tf", "7"), ("scans scored", "2"),
        ("scans skipped: no pose at its time", "1"), ("scans dropped from a full queue", "4"),
        ("time jumps back", "1"), ("latency median (ms)", "2.00"), ("latency 99th percentile (ms)", "2.00")]
    for clock in (5.0, 5.5, 6.25):
        stats.scan_arrived(clock)
    assert stats.summary() == "3 scan messages in 1.25 s, 2 scans scored, 1 skipped, 4 dropped from a full queue; " \
                              "latency median 2.00 ms, 99th percentile 2.00 ms"
