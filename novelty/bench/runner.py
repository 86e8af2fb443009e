"""A whole run: skip finished cells, execute the rest, record, summarise, plot."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence, TextIO

from .._atomic import write_atomically
from .backends import execute
from .compare import compare_on_task, comparison_text
from .definition import DEFINITION_COLUMN, definition_digest
from .progress import Progress
from .protocol import get_protocol
from .reports.critical_difference import plot_critical_difference
from .reports.figures import matplotlib_missing
from .reports.statistics import paired_text
from .reports.summary import summary_markdown, warnings_note
from .results import ResultsStore, provenance
from .suite import Suite

__all__ = ["run_bench", "BenchReport"]


@dataclass
class BenchReport:
    """What a run did and where it wrote it."""

    out: Path
    rows: list[dict]                    # every cell of the suite, old and new
    ran: int = 0
    skipped: int = 0
    stale: int = 0                      # finished cells recomputed: their definition changed since
    failed: int = 0
    interrupted: bool = False
    files: list[Path] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    reference: str | None = None        # the paired comparison's reference (the suite's, else its first detector)
    protocol: str = "holdout"
    comparisons: list[str] = field(default_factory=list)  # the single-task comparisons (markdown lines)

    @property
    def table(self) -> str:
        """The protocol's table, then the paired comparison with the reference."""
        paired = paired_text(self.rows, self.reference)
        return get_protocol(self.protocol).table(self.rows).rstrip() + (f"\n\n{paired}" if paired else "")


def run_bench(suite: Suite, out, backend: str = "serial", jobs: int = 1, scheduler: str | None = None,
              plots: bool = True, progress: TextIO | None = None, quiet: bool = False,
              client=None, command: str | None = None, compare_on: Sequence[str] = ()) -> BenchReport:
    """Run ``suite`` into the folder ``out`` and return a :class:`BenchReport`.

    Cells already finished in ``out/results.jsonl`` are skipped (resume), but
    for those whose detector or task resolves to something else now than
    when their rows were computed (:mod:`novelty.bench.definition`; rows that
    record no definition count as changed): these are recomputed, and the
    run says how many.
    The run holds ``out`` (:meth:`ResultsStore.lock`): a second run into
    the same folder raises :class:`~novelty.bench.results.OutputBusyError`.
    ``backend`` is ``"serial"``, ``"joblib"`` (``jobs`` processes) or
    ``"dask"`` (the scheduler at ``scheduler``, or a local cluster of ``jobs``
    workers; or an existing ``client``). ``command``, the command line that
    started the run, is recorded in ``summary.md`` with the versions and revision.
    ``compare_on`` names tasks on which each detector is compared with the
    reference by a paired bootstrap over test scans (:mod:`novelty.bench.compare`);
    a hold-out run of one task gets that comparison whether asked or not.
    """
    store = ResultsStore(out)
    store.prepare()
    with store.lock():
        return _run(suite, store, backend, jobs, scheduler, plots, progress, quiet, client, command,
                    list(compare_on))


def _skip_notices(suite: Suite) -> list[str]:
    """One line per reason: which optional entries were skipped, and what would run them."""
    by_reason: dict[str, list[str]] = {}
    for name in suite.skipped:
        by_reason.setdefault(suite.skip_reasons.get(name, "not registered here"), []).append(name)
    return [f"Skipped {', '.join(names)}: {reason}." for reason, names in by_reason.items()]


def _run(suite: Suite, store: ResultsStore, backend: str, jobs: int, scheduler: str | None,
         plots: bool, progress: TextIO | None, quiet: bool, client, command: str | None,
         compare_on: list[str]) -> BenchReport:
    cells = list({c.id: c for c in suite.cells()}.values())
    finished = store.finished()
    found = [c for c in cells if c.id in finished]
    stream = progress if progress is not None else sys.stderr
    if found and not quiet:  # each task is loaded again to be compared: seconds a task
        print(f"Checking {len(found)} finished cells in {store.jsonl} against what their detectors and "
              "tasks resolve to now.", file=stream)
    stale = {c.id for c in found if not _still_defined(c, finished[c.id])}
    todo = [c for c in cells if c.id not in finished or c.id in stale]
    report = BenchReport(store.out, [], skipped=len(cells) - len(todo), stale=len(stale),
                         reference=suite.reference_label, protocol=suite.protocol)
    protocol = get_protocol(suite.protocol)
    if report.skipped and not quiet:
        print(f"Resuming: {report.skipped} of {len(cells)} cells already in {store.jsonl}.", file=stream)
    if stale:
        notice = (f"{len(stale)} of the {len(found)} finished cells were computed by another definition of "
                  "their detector or task than they resolve to now (a preset or a task changed since, or "
                  "their rows record none); recomputing them.")
        report.notes.append(notice)
        if not quiet:
            print(notice, file=stream)
    for notice in _skip_notices(suite):
        report.notes.append(notice)
        if not quiet:
            print(notice, file=stream)
    stamp = provenance()
    try:
        with Progress(len(todo), stream=stream, quiet=quiet) as bar:
            for row, arrays in execute(todo, backend, jobs, scheduler, client=client):
                row.update(stamp)
                store.append(row, arrays)
                report.ran += 1
                bar.update(row)
    except KeyboardInterrupt:
        report.interrupted = True
    ids = {c.id for c in cells}
    report.rows = [r for r in store.rows() if r["cell_id"] in ids]
    report.failed = sum(r.get("status") != "ok" for r in report.rows)
    report.files.append(store.write_csv())
    report.files.append(store.jsonl)
    if suite.threshold != "max":
        report.notes.append(f"Alarm threshold: the {suite.threshold} quantile of the training novelty.")
    summary = store.out / "summary.md"
    if not compare_on and len(suite.tasks) == 1 and suite.protocol == "holdout":
        compare_on = [suite.tasks[0].label]
    warned = warnings_note(report.rows)
    if warned:
        report.notes.append(warned)
    report.comparisons = _comparisons(report.rows, store, compare_on, suite.reference_label, suite.protocol)
    sections = protocol.summary(report.rows) + report.comparisons
    text = summary_markdown(report.rows, f"Benchmark: {suite.name}", report.notes, suite.reference_label,
                            {**stamp, "command": command}, sections, suite.reference_how)
    write_atomically(summary, lambda fh: fh.write(text), text=True)
    report.files.append(summary)
    if plots and report.rows and not report.interrupted:
        missing = matplotlib_missing()
        if missing:
            report.notes.append(missing)
        else:
            folder = store.out / "plots"
            report.files.extend(protocol.plots(report.rows, store.arrays, folder))
            report.files.extend(plot_critical_difference(report.rows, folder))
    return report


def _still_defined(cell, row: dict) -> bool:
    """Whether a finished cell's row was computed by what the cell resolves to now."""
    recorded = row.get(DEFINITION_COLUMN)
    if not recorded:
        return False
    try:
        return definition_digest(cell) == recorded
    except Exception:  # noqa: BLE001 - what cannot be built now is run again, and fails as a cell
        return False


#: what one single-task comparison resamples or pairs, by protocol
_COMPARISON_UNIT = {"holdout": "the test scan", "exploration": "the seed, each an independently built world"}


def _comparisons(rows: list[dict], store: ResultsStore, tasks: list[str], reference: str | None,
                 protocol: str = "holdout") -> list[str]:
    """The summary's sections of single-task comparisons (markdown lines)."""
    lines = []
    for task in tasks:
        try:
            text = comparison_text(compare_on_task(rows, store.arrays, task, reference))
        except ValueError as exc:
            text = f"No comparison on {task}: {exc}"
        lines += ["", f"## Comparison on one task: {task}", "",
                  f"Unit: {_COMPARISON_UNIT.get(protocol, 'the test scan')}. For a verdict on this task alone, "
                  "not across tasks.", "", text]
    return lines
