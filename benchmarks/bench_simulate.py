"""Time to simulate one 10 m run of each paper environment (median of several).

Wall-clock time depends on what else the machine runs; CPU time (the
process's own) is the steadier figure.

Run: ``python benchmarks/bench_simulate.py [--repeats 7]``. Prints a table;
not a unit test (timings depend on the machine and its load).
"""

from __future__ import annotations

import argparse
import statistics
import time

from novelty import sonar
from novelty.tasks.inspection import generate_corridor


def _time(env, repeats: int) -> tuple[float, float, int]:
    """Median wall-clock and median CPU seconds of one run, and the scans it gives."""
    wall, cpu = [], []
    for run in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        ds = sonar.simulate_run(env, seed=0, run=run)
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return statistics.median(wall), statistics.median(cpu), len(ds)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    sonar.simulate_run("a", 0, 0)  # warm up imports and caches
    rows = [(name, *_time(name, args.repeats)) for name in sonar.environment_names()]
    corridor = generate_corridor(0, length=10.0).build()
    rows.append(("generated corridor 0", *_time(corridor, args.repeats)))
    print(f"{'environment':22s} {'wall (s)':>9s} {'cpu (s)':>8s} {'scans':>6s}   (medians)")
    for name, wall, cpu, n in rows:
        print(f"{name:22s} {wall:9.3f} {cpu:8.3f} {n:6d}")


if __name__ == "__main__":
    main()
