"""The benchmark harness: detectors x tasks x seeds, scored as a robot would use them.

>>> from novelty.bench import DetectorSpec, TaskSpec, Suite
>>> suite = Suite([DetectorSpec("hsom")], [TaskSpec("my-task")], seeds=[0, 1])
>>> len(suite.cells())                                   # doctest: +SKIP
2

From Python, :func:`run` benchmarks detectors (names or objects) on tasks
(names, task objects, arrays) and returns :class:`Results`
(:mod:`novelty.bench.benchmark`). A run is a :class:`Suite` (read from TOML
with :func:`load_suite`, or built in code or on the command line) executed
by :func:`run_bench` into an output folder: ``results.jsonl``,
``results.csv``, ``summary.md`` and ``plots/``.

The package by job:

- what to run: :mod:`~novelty.bench.specs` (detectors, tasks, cells, seeds),
  :mod:`~novelty.bench.suite` (a suite and its checks,
  :mod:`~novelty.bench.spec_checks`), :mod:`~novelty.bench.suite_file`
  (TOML);
- the protocols, each one sub-package with its evaluation, metrics, summary
  and plots behind one :class:`~novelty.bench.protocol.Protocol`:
  :mod:`~novelty.bench.holdout` and :mod:`~novelty.bench.exploration`;
- running cells: :mod:`~novelty.bench.cell`, :mod:`~novelty.bench.build`,
  :mod:`~novelty.bench.backends`, :mod:`~novelty.bench.runner`,
  :mod:`~novelty.bench.progress`, :mod:`~novelty.bench.results`,
  :mod:`~novelty.bench.river`;
- statistics: :mod:`~novelty.bench.stats`;
- reports shared by the protocols (tables, summary, critical-difference
  diagram): :mod:`~novelty.bench.reports`.

Shares its name with ``novelty/cli/bench.py``: the benchmark, and the command that runs it (a
command's module is named after the command).
"""

from .specs import Cell, DetectorSpec, SuiteError, TaskSpec, parse_seeds
from .suite import Suite
from .suite_file import load_suite, quick_suite_path, suite_from_dict

__all__ = [
    "Cell",
    "DetectorSpec",
    "TaskSpec",
    "Suite",
    "SuiteError",
    "load_suite",
    "suite_from_dict",
    "quick_suite_path",
    "parse_seeds",
    "run_bench",
    "run_cell",
    "run",
    "Results",
]


def __getattr__(name):
    if name in ("run", "Results", "run_suite"):
        # deferred: a run imports the backends, results and plots; the specs need none of them
        from . import benchmark

        return getattr(benchmark, name)
    if name == "run_bench":
        # deferred: the runner imports the backends, results and plots; the specs need none of them
        from .runner import run_bench

        return run_bench
    if name == "run_cell":
        # deferred: a cell imports every detector's machinery
        from .cell import run_cell

        return run_cell
    raise AttributeError(f"module 'novelty.bench' has no attribute {name!r}")
