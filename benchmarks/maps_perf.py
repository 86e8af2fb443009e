"""How fast the maps stream a real drive: scans a second of the habituating maps and the occupancy grid.

Run::

    NOVELTY_DATA_DIR=/work/shared/datasets taskset -c 1 python benchmarks/maps_perf.py [--repeats N] [--log intel]

The drive is a Radish log's scans with their poses (``intel`` by default: 180
beams over the front half), read once. Each configuration turns the sweeps
into ``points`` rows with :func:`novelty.io.scans.points.sweep_points` and
times, for every detector in a fresh instance (its compiled loop compiled or
loaded first, on the first 50 rows, and waited for), median over the
repetitions of the process's CPU time (``time.process_time``: what the work
costs on one core, less sensitive than wall time to what else runs on a
shared machine):

- ``rows``: building the rows from the sweeps (the same for every detector);
- ``stream``: every row scored, then learned, in order (``stream``: the
  exploration protocol's online policy);
- ``score``: every row scored by a detector fitted on all of them (``novelty``:
  the hold-out protocol's frozen form);
- scans a second of ``rows + stream``, what a robot feeding the detector its
  sweeps pays, and of ``stream`` alone; the ratio of a detector's stream time to
  the occupancy grid's in the same configuration.

The configurations: 180 sectors cut at 4 m (the objects tasks' rows); 1,080
sectors cut at 4 m, from the same sweeps with each scan's ranges interpolated to
1,080 beams over the same angles (a laser of a sixth of a degree); 180
sectors cut at 2, 8 and 16 m (the cost's growth with range: the map's
``max_range`` is 20 m so that nothing is cut twice); and 180 sectors cut at 4
m read in cells half as wide as each detector's own (``cells`` x0.5: its
growth with the cells a ray crosses).

Not a unit test: the figures depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from functools import partial

import numpy as np

import novelty
from novelty import _kernels
from novelty.io.scans.points import sweep_points
from novelty.tasks.objects.object_tasks import read_drive
from novelty.tasks.radish import radish_log

#: the occupancy grid first: each map's time is set beside its time in the same configuration
DETECTORS = ("occupancy-grid", "habituating-map", "map-explore")
#: (sectors, beams a sweep, threshold in m, cells as a share of each detector's own): 180 beams are the log's own
CONFIGURATIONS = ((180, 180, 4.0, 1.0), (1080, 1080, 4.0, 1.0), (180, 180, 2.0, 1.0), (180, 180, 8.0, 1.0),
                  (180, 180, 16.0, 1.0), (180, 180, 4.0, 0.5))
#: the maps' reach (m): beyond the longest threshold, so that a sector is cut once, by sweep_points
MAX_RANGE = 20.0


def resampled(sweeps, beams: int):
    """Each sweep with its ranges interpolated to ``beams`` beams evenly over the same angles (no echo where
    either neighbour has none); the sweeps as they are when they already have ``beams``."""
    out = []
    for sweep in sweeps:
        if len(sweep.ranges) == beams:
            out.append(sweep)
            continue
        angles = np.linspace(sweep.angles[0], sweep.angles[-1], beams)
        ranges = np.interp(angles, sweep.angles, sweep.ranges)   # inf beside a beam without echo stays inf
        origins = np.broadcast_to(sweep.origins.mean(axis=0), (beams, 2)).copy()
        out.append(dataclasses.replace(sweep, angles=angles, ranges=ranges, origins=origins, spread=None))
    return out


def timed(work, repeats: int) -> float:
    """The median CPU time of ``work()`` over ``repeats`` calls (s)."""
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        work()
        times.append(time.process_time() - t0)
    return statistics.median(times)


def detector(name: str, cells: float = 1.0):
    """A fresh ``name`` reaching ``MAX_RANGE``, its cells ``cells`` times as wide as its own."""
    own = novelty.make(name)
    size = own.cell_size if hasattr(own, "cell_size") else own.clusterer.cell_size
    return novelty.make(name, max_range=MAX_RANGE, cell_size=size * cells)


def stream(name: str, cells: float, X) -> None:
    """A fresh ``name`` streams ``X``: each row scored, then learned."""
    detector(name, cells).stream(X)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--log", default="intel", choices=("intel", "aces", "csail"))
    args = parser.parse_args()
    sweeps = read_drive(radish_log(args.log))
    _kernels.wait()
    print(f"Radish {args.log}: {len(sweeps)} scans with poses; median CPU time of {args.repeats} repetitions")
    print("| sectors | beams | range, m | cells | detector | rows, s | stream, s | score, s "
          "| scans/s (rows + stream) | scans/s (stream) | stream / occupancy-grid's |")
    print("| ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for sectors, beams, threshold, cells in CONFIGURATIONS:
        drive = resampled(sweeps, beams)
        X = sweep_points(drive, sectors, threshold)   # the rows' kernel compiled or loaded first
        rows = timed(partial(sweep_points, drive, sectors, threshold), args.repeats)
        streams = {}
        for name in DETECTORS:
            detector(name, cells).stream(X[:50])   # compile or load its loop,
            _kernels.wait()                        # and wait for it: nothing compiles while timed
            streams[name] = timed(partial(stream, name, cells, X), args.repeats)
            score = timed(partial(detector(name, cells).fit(X).novelty, X), args.repeats)
            n = len(X)
            print(f"| {sectors} | {beams} | {threshold:g} | x{cells:g} | {name} | {rows:.3f} | {streams[name]:.3f} | {score:.3f} "
                  f"| {n / (rows + streams[name]):,.0f} | {n / streams[name]:,.0f} "
                  f"| {streams[name] / streams['occupancy-grid']:.2f} |")


if __name__ == "__main__":
    main()
