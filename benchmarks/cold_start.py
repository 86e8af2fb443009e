"""A user's first and second command from an empty compile cache: ``novelty bench --quick`` twice in a row.

Each repetition gives numba a fresh, empty cache (``NUMBA_CACHE_DIR``, which
holds the generated drivers too), runs the quick suite, then at once the same
command again, then a third time once every compiler the first two left has
finished (the warm reference). Wall time, and CPU time of the command and the
children it waited for (``RUSAGE_CHILDREN``; compilers left running after a
command ends are not its own), medians over the repetitions:

    python benchmarks/cold_start.py --repeat 3 --out cold-start.json

The machine's load (the 1-minute load average before each run) is recorded
beside each run: timings on a shared machine are read as ratios of runs made
together.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COMMAND = [sys.executable, "-m", "novelty.cli", "bench", "--quick", "--quiet", "--no-plots"]


def timed(env: dict, out: Path) -> dict:
    """One command: its wall time and the CPU time of the command and the children it waited for."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load = os.getloadavg()[0]
    start = time.perf_counter()
    subprocess.run([*COMMAND, "--out", str(out)], env=env, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall_s": round(wall, 2), "cpu_s": round(cpu, 2), "load": round(load, 2)}


def settled(cache: Path, timeout: float = 1800.0) -> float:
    """Wait until no process left by the commands still runs (each has ``NUMBA_CACHE_DIR`` = ``cache`` in its
    environment: the compilers a command left behind); the seconds waited."""
    marker = f"NUMBA_CACHE_DIR={cache}".encode()
    start = time.perf_counter()
    while time.perf_counter() - start < timeout:
        if not any(marker in _environment(pid) for pid in os.listdir("/proc") if pid.isdigit()):
            break
        time.sleep(1.0)
    return time.perf_counter() - start


def _environment(pid: str) -> bytes:
    try:
        return Path(f"/proc/{pid}/environ").read_bytes()
    except OSError:   # gone, or another user's
        return b""


def repetition(root: Path) -> dict:
    cache = root / "cache"
    cache.mkdir()
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    first = timed(env, root / "first")
    second = timed(env, root / "second")
    waited = settled(cache)
    warm = timed(env, root / "warm")
    return {"first": first, "second": second, "settled_after_s": round(waited, 1), "warm": warm}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", type=Path, help="write every run here (JSON)")
    args = parser.parse_args(argv)
    runs = []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory(prefix="novelty-cold-start-") as tmp:
            runs.append(repetition(Path(tmp)))
        print(json.dumps(runs[-1]), file=sys.stderr)
    table = {k: {m: statistics.median(r[k][m] for r in runs) for m in ("wall_s", "cpu_s", "load")}
             for k in ("first", "second", "warm")}
    print("| run | wall (s) | CPU (s) | load before |\n| --- | ---: | ---: | ---: |")
    for k, v in table.items():
        print(f"| {k} | {v['wall_s']:.1f} | {v['cpu_s']:.1f} | {v['load']:.1f} |")
    if args.out:
        args.out.write_text(json.dumps({"runs": runs, "medians": table}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
