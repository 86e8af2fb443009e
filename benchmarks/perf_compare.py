"""Two revisions of the package, timed against each other on one machine, alternately.

Run::

    git worktree add /tmp/before <revision>     # the revision to compare with
    python benchmarks/perf_compare.py /tmp/before . [--rounds 3] [--core 0]

``perf.py`` compares the package with its peers (MiniSom, River, its own
numpy loop) within one run; comparing two revisions by two runs of it, an
hour apart, compares two states of a shared machine as much as two
revisions (the ratio to MiniSom moved by a third between two such runs, the
package's code unchanged). This script times the same cases in the two
trees in turn, a fresh process each, ``--rounds`` times (before, after,
before, after, ...), each with its own numba cache (compiled and loaded
before any timing), pinned to one core where the system allows; a case's
figure is the median over the rounds of each process's median, and the
ratio is before / after (above 1: the second tree is faster), with each
round's ratio beside it.

The cases are what a change to the engine or the filter's checks touches:

- ``learning <pair>``: every registered clusterer x synapse pair with its
  defaults (as ``perf.py``'s rows: fitted on two scans, its driver ready), a
  fresh deep copy's first ``stream`` of 1,000 corridor scans (the copy not
  timed): the engine it makes, the checks and the learning;
- ``hsom stream 5000``: a fresh copy's first stream of 5,000 scans;
- one call of each kind on a warm ``hsom``: ``stream`` and ``score_samples``
  of one scan (a batch call's fixed costs), ``score_learn_one`` and
  ``score_one``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

#: the child's program: the tree's own package and corridor (``benchmarks/perf.py``)
CHILD = r"""
import copy, json, sys, time
import numpy as np
tree = sys.argv[1]
sys.path[:0] = [tree, tree + "/benchmarks"]
import novelty
from novelty import _kernels
from perf import corridor_stream

X = corridor_stream(1000)
out = {}

def first_streams(det, X, n):
    for _ in range(3):  # warm: the driver loaded, the caches of the process filled
        copy.deepcopy(det).stream(X)
    times = []
    for _ in range(n):
        fresh = copy.deepcopy(det)
        start = time.perf_counter()
        fresh.stream(X)
        times.append(time.perf_counter() - start)
    return float(np.median(times))

for c in sorted(novelty.available("clusterers")):
    for s in sorted(novelty.available("synapses")):
        det = novelty.HabituatingFilter(clusterer=c, synapse=s).fit(X[:2])
        _kernels.wait(det.clusterer_, det.synapse_)
        out[f"learning {c} x {s}, 1000 scans"] = first_streams(det, X, 25)
det = novelty.make("hsom").fit(X[:2])
_kernels.wait(det.clusterer_, det.synapse_)
out["hsom stream, 5000 scans"] = first_streams(det, corridor_stream(5000), 15)
warm = copy.deepcopy(det)
warm.stream(X)
for name, call in [("stream of one scan", lambda: warm.stream(X[:1])),
                   ("score_samples of one scan", lambda: warm.score_samples(X[:1])),
                   ("score_learn_one", lambda: warm.score_learn_one(X[5])),
                   ("score_one", lambda: warm.score_one(X[5]))]:
    for _ in range(200):
        call()
    times = []
    for _ in range(15):
        start = time.perf_counter()
        for _ in range(200):
            call()
        times.append((time.perf_counter() - start) / 200)
    out[name] = float(np.median(times))
print(json.dumps(out))
"""


def measure(tree: str, cache: str, core: int | None) -> dict:
    """One child's medians (seconds per call) in ``tree``, with numba's cache in ``cache``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache}
    env.pop("PYTHONPATH", None)  # the tree is put first on the child's path, nothing else
    command = [sys.executable, "-c", CHILD, os.path.abspath(tree)]
    if core is not None and shutil.which("taskset"):
        command = ["taskset", "-c", str(core)] + command
    done = subprocess.run(command, env=env, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"timing {tree} failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def table(before: list[dict], after: list[dict]) -> str:
    """A markdown table: each case's medians over the rounds, the ratio and each round's."""
    lines = ["| case | before (us) | after (us) | before / after | each round |", "|---|---|---|---|---|"]
    for case in before[0]:
        b = float(np.median([r[case] for r in before]))
        a = float(np.median([r[case] for r in after]))
        rounds = " ".join(f"{x[case] / y[case]:.2f}" for x, y in zip(before, after))
        lines.append(f"| {case} | {b * 1e6:.1f} | {a * 1e6:.1f} | {b / a:.3f} | {rounds} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before", help="the tree of the revision to compare with")
    parser.add_argument("after", help="the tree of the revision compared")
    parser.add_argument("--rounds", type=int, default=3, help="alternations (default 3)")
    parser.add_argument("--core", type=int, default=0, help="the core to pin to (-1: none)")
    args = parser.parse_args(argv)
    core = None if args.core < 0 else args.core
    before: list[dict] = []
    after: list[dict] = []
    with tempfile.TemporaryDirectory() as cache_before, tempfile.TemporaryDirectory() as cache_after:
        # untimed, twice each: the first compiles into each cache, and a compiler the first
        # process left running (it does not wait for them at exit) finishes during the second
        for _ in range(2):
            measure(args.before, cache_before, core)
            measure(args.after, cache_after, core)
        for i in range(args.rounds):
            before.append(measure(args.before, cache_before, core))
            after.append(measure(args.after, cache_after, core))
            print(f"round {i + 1}/{args.rounds} done", file=sys.stderr)
    print(table(before, after))
    return 0


if __name__ == "__main__":
    sys.exit(main())
