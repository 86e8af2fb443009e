"""How fast the exploration protocol streams: 10,000 scans through compiled habituating detectors.

Run::

    python benchmarks/exploration_perf.py [--repeats N] [--scans N]

The scans are real exploration scans (``exploration-open-door``, seeds 0, 1,
... concatenated until ``--scans``). For each detector, the compiled kernels
are made ready first (compiled once per machine into numba's cache; see
:mod:`novelty._kernels`), then every repetition times, in a fresh detector:

- ``stream``: every scan scored, then learned, in order (the online policy);
- ``cell``: :func:`novelty.bench.exploration.prequential.prequential` plus every metric of
  the exploration row (what a benchmark cell computes after loading its task).

Prints the median over the repetitions. Not a unit test: the numbers depend on
the machine and on what else it is doing.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import novelty
from novelty import _kernels
from novelty.bench.exploration.prequential import exploration_metrics, prequential
from novelty.tasks.exploration import open_door

DETECTORS = ("hsom", "som-wang-hsu", "gwr-novelty", "gwr-explore", "gng-stanley")


def scans(n: int):
    """``n`` scans of door explorations, with their labels, runs numbered in order."""
    parts, seed = [], 0
    while sum(len(p.X) for p in parts) < n:
        parts.append(open_door(seed=seed))
        seed += 1
    X = np.vstack([p.X for p in parts])[:n]
    offset = np.cumsum([0] + [int(p.run.max()) + 1 for p in parts[:-1]])
    run = np.concatenate([p.run + o for p, o in zip(parts, offset)])[:n]
    feature = np.concatenate([p.columns["feature"] for p in parts])[:n]
    exposure = np.concatenate([p.columns["exposure"] for p in parts])[:n]
    return X, run, feature, exposure


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scans", type=int, default=10_000)
    args = parser.parse_args()
    X, run, feature, exposure = scans(args.scans)
    _kernels.wait()
    print(f"{len(X)} scans of 16 sensors; median of {args.repeats} repetitions")
    print("| detector | stream, s | scans/s | cell (stream + metrics), s |")
    print("| --- | ---: | ---: | ---: |")
    for name in DETECTORS:
        novelty.make(name, random_state=0).stream(X[:50])  # first call: load the kernels
        streams, cells = [], []
        for _ in range(args.repeats):
            det = novelty.make(name, random_state=0)
            t0 = time.perf_counter()
            det.stream(X)
            streams.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            out, det = prequential(lambda name=name: novelty.make(name, random_state=0), X, run, 3)
            exploration_metrics(out, run, feature, exposure, 3, {}, 0.0)
            cells.append(time.perf_counter() - t0)
        s, c = statistics.median(streams), statistics.median(cells)
        print(f"| {name} | {s:.3f} | {len(X) / s:,.0f} | {c:.3f} |")


if __name__ == "__main__":
    main()
