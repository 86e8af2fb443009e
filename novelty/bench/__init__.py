"""The benchmark harness: detectors x tasks x seeds, scored as a robot would use them.

>>> from novelty.bench import DetectorSpec, TaskSpec, Suite
>>> suite = Suite([DetectorSpec("hsom")], [TaskSpec("my-task")], seeds=[0, 1])
>>> len(suite.cells())                                   # doctest: +SKIP
2

A run is a :class:`Suite` (read from TOML with :func:`load_suite`, or built in
code or on the command line) executed by :func:`run_bench` into an output
folder: ``results.jsonl``, ``results.csv``, ``summary.md`` and ``plots/``.
Each cell is :func:`novelty.bench.cell.run_cell`; the metrics are in
:mod:`novelty.bench.metrics`.
"""

from .suite import Cell, DetectorSpec, Suite, SuiteError, TaskSpec, load_suite, quick_suite_path

__all__ = [
    "Cell",
    "DetectorSpec",
    "TaskSpec",
    "Suite",
    "SuiteError",
    "load_suite",
    "quick_suite_path",
    "run_bench",
    "run_cell",
]


def __getattr__(name):
    if name == "run_bench":
        # deferred: the runner imports the backends, results and plots; the specs need none of them
        from .runner import run_bench

        return run_bench
    if name == "run_cell":
        # deferred: a cell imports every detector's machinery
        from .cell import run_cell

        return run_cell
    raise AttributeError(f"module 'novelty.bench' has no attribute {name!r}")
