"""Comparing detectors on one task of a run: the paired bootstrap and the corrected t-test.

:func:`compare_on_task` reads a run's rows and the per-scan arrays its cells
kept (the novelty ``novelty`` and labels ``y`` of every test scan,
``cells/<cell_id>.npz``) and sets each detector against a reference on one
task (:mod:`novelty.bench.stats.single_task`):

- a paired, stratified bootstrap over the test scans of one seed (the
  smallest): the interval of the difference of ROC AUC and of average
  precision;
- when the task's seeds draw different splits (the reference's values
  differ between seeds), the corrected resampled t-test over the seeds.

An exploration task's cells keep no labels to resample: there the unit is
the seed, when each seed builds its own world (the rows' ``task_data``
differ from seed to seed; :mod:`novelty.bench.definition`). The worlds are
independent, so the mean of the per-seed differences of first-encounter ROC
AUC gets the plain Student-t interval on ``J - 1`` degrees of freedom (no
correction for shared training data, which worlds do not share; five seeds
are too few for a bootstrap's percentile interval). Seeds that ran on one
world (a recording: the seed moves only the detector) are no sample of
worlds, and get no interval.

:func:`comparison_text` writes the records as a table (``novelty bench
--compare-on-task``, and :meth:`novelty.bench.Results.compare_on_task`).
"""

from __future__ import annotations

import math
from typing import Callable, Sequence


from .definition import TASK_DATA_COLUMN
from .reports.format import format_table, p_value, signed
from .reports.ranking import reference_of
from .stats.aggregate import CONFIDENCE, as_float, distinct, mean, seed_interval
from .stats.single_task import RESAMPLES, corrected_resampled_t, paired_bootstrap

__all__ = ["compare_on_task", "comparison_text"]


def _cells(rows: Sequence[dict], task: str) -> dict[str, list[dict]]:
    out: dict[str, list[dict]] = {}
    for r in sorted(rows, key=lambda r: int(r["seed"])):
        if r["task"] == task and r.get("status") == "ok":
            out.setdefault(r["detector"], []).append(r)
    return out


def compare_on_task(rows: Sequence[dict], arrays: Callable[[str], dict | None], task: str,
                    reference: str | None = None, resamples: int = RESAMPLES, seed: int = 0) -> list[dict]:
    """Each detector against ``reference`` (default: the first by label; a run passes its suite's) on ``task``.

    Returns one record a detector (the reference left out) with the
    bootstrap intervals ``roc_auc`` and ``average_precision``
    (:class:`~novelty.bench.stats.single_task.Bootstrap`), the seed they
    used, and ``corrected_t`` (:class:`~novelty.bench.stats.single_task.CorrectedT`,
    or None when the seeds repeat one split or a count of scans is missing).
    On an exploration task each record holds instead the mean ``difference``
    of first-encounter ROC AUC over the ``seeds`` both completed, its
    Student-t interval ``low``, ``high`` (NaN unless ``worlds`` is
    ``"built"``: ``"one"`` for seeds of one recording, ``"unknown"`` for rows
    that do not record their task's data) and ``metric``.
    """
    cells = _cells(rows, task)
    if not cells:
        known = sorted({r["task"] for r in rows})
        raise ValueError(f"No successful cell of task {task!r}; tasks of this run: {', '.join(known)}.")
    reference = reference_of(rows, reference)
    if reference not in cells:
        raise ValueError(f"The reference {reference!r} has no successful cell on {task!r}; "
                         f"detectors there: {', '.join(cells)}.")
    if all(r.get("policy") for found in cells.values() for r in found):  # exploration cells
        return [_over_worlds(task, detector, mine, reference, cells[reference])
                for detector, mine in cells.items() if detector != reference]
    ref_cell = cells[reference][0]
    ref_arrays = arrays(ref_cell["cell_id"])
    if ref_arrays is None or "y" not in ref_arrays:
        raise ValueError(f"The cells of {task!r} kept no per-scan novelty and labels (hold-out cells keep "
                         "them in cells/<cell_id>.npz); rerun it into a folder to compare on it.")
    records = []
    for detector, mine in cells.items():
        if detector == reference:
            continue
        same_seed = next((r for r in mine if r["seed"] == ref_cell["seed"]), None)
        a = arrays(same_seed["cell_id"]) if same_seed is not None else None
        if a is None:
            continue
        record = {"detector": detector, "reference": reference, "task": task, "seed": ref_cell["seed"]}
        for metric in ("roc_auc", "average_precision"):
            record[metric] = paired_bootstrap(a["novelty"], ref_arrays["novelty"], ref_arrays["y"], metric,
                                              resamples, seed)
        record["corrected_t"] = _corrected_t(mine, cells[reference])
        records.append(record)
    return records


def _corrected_t(mine: list[dict], ref: list[dict]):
    """The corrected resampled t-test over the seeds both completed, if the seeds draw different splits."""
    by_seed = {r["seed"]: r for r in ref}
    pairs = [(r, by_seed[r["seed"]]) for r in mine if r["seed"] in by_seed]
    if len(pairs) < 2 or distinct([as_float(b.get("roc_auc")) for _, b in pairs]) < 2:
        return None
    n_train, n_test = as_float(pairs[0][1].get("n_train")), as_float(pairs[0][1].get("n_test"))
    if not (n_train > 0 and n_test > 0):
        return None
    d = [as_float(a.get("roc_auc")) - as_float(b.get("roc_auc")) for a, b in pairs]
    return corrected_resampled_t(d, int(n_train), int(n_test))


#: what an exploration cell is compared by
EXPLORATION_METRIC = "first_encounter_auc"


def _over_worlds(task: str, detector: str, mine: list[dict], reference: str, ref: list[dict]) -> dict:
    """One detector against the reference over the seeds both completed, each seed one world."""
    by_seed = {r["seed"]: r for r in ref}
    pairs = [(r, by_seed[r["seed"]]) for r in mine if r["seed"] in by_seed]
    d = [as_float(a.get(EXPLORATION_METRIC)) - as_float(b.get(EXPLORATION_METRIC)) for a, b in pairs]
    worlds = [b.get(TASK_DATA_COLUMN) for _, b in pairs]
    if not all(worlds):
        kind = "unknown"   # rows recorded before their task's data was
    elif len(set(worlds)) == len(worlds) > 1:
        kind = "built"
    else:
        kind = "one"
    low, high = seed_interval(d, bounds=(-1.0, 1.0)) if kind == "built" else (float("nan"), float("nan"))
    return {"detector": detector, "reference": reference, "task": task, "metric": EXPLORATION_METRIC,
            "seeds": len(pairs), "worlds": kind, "difference": mean(d), "low": low, "high": high}


def _interval(b) -> str:
    return f"{signed(b.difference)} [{b.low:+.3f}, {b.high:+.3f}]" + (" *" if b.excludes_zero else "")


def comparison_text(records: Sequence[dict]) -> str:
    """The comparisons on one task as a table (* : the interval excludes zero)."""
    if not records:
        return ""
    first = records[0]
    if "worlds" in first:
        return _worlds_text(records)
    level = f"{first['roc_auc'].confidence:.0%}"
    header = ["detector", f"ΔROC AUC vs {first['reference']} [{level} CI]", f"ΔAP [{level} CI]",
              "Δ over seeds, corrected t (p)"]
    body = []
    for r in records:
        t = r["corrected_t"]
        body.append([r["detector"], _interval(r["roc_auc"]), _interval(r["average_precision"]),
                     "-" if t is None else f"{signed(t.mean)}, t = {t.t:.2f} ({p_value(t.pvalue)}, "
                                           f"{t.n_splits} seeds)"])
    return (f"Paired bootstrap over the test scans of {first['task']}, seed {first['seed']} "
            f"({first['roc_auc'].resamples:,} stratified resamples, seed 0); * : the interval excludes 0.\n\n"
            + format_table(header, body))


_NO_INTERVAL = {"one": "one world: no interval", "unknown": "worlds not recorded: no interval"}


def _worlds_text(records: Sequence[dict]) -> str:
    first = records[0]
    body = []
    for r in records:
        if r["worlds"] != "built":
            interval = _NO_INTERVAL[r["worlds"]]
        elif math.isnan(r["low"]):
            interval = "one value on every seed"
        else:
            interval = f"[{r['low']:+.3f}, {r['high']:+.3f}]" + (" *" if r["low"] > 0 or r["high"] < 0 else "")
        body.append([r["detector"], signed(r["difference"]), interval, str(r["seeds"])])
    header = ["detector", f"Δfirst-encounter AUC vs {first['reference']} (mean over seeds)",
              f"{CONFIDENCE:.0%} CI (Student t)", "seeds"]
    return (f"Paired over the seeds of {first['task']}, each seed an independently built world (unit: the "
            "seed); a task whose seeds share one world (a recording) gets no interval; * : the interval "
            "excludes 0.\n\n" + format_table(header, body))
