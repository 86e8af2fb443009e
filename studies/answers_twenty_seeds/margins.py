"""How wide a guard's margin is: each detector's mean ROC AUC per task with a 95 % interval over its seeds.

    python studies/answers_twenty_seeds/margins.py results/answers-ring results/answers-points \
        [--pair kmeans-stanley parzen]

Reads the runs' ``results.jsonl`` (the hold-out protocol: one ROC AUC a detector, task and seed) and
prints, one line a detector and task: the mean over the seeds, its standard deviation, the 95 %
interval of the mean (Student's t with n - 1 degrees of freedom: mean ± t · sd / sqrt(n)), the seeds at
or below 0.5, and where the interval lies: "above chance" (its lower end above 0.5), "below chance"
(its upper end below 0.5) or "at chance" (it holds 0.5). ``--pair A B`` adds, for two detectors run on
the same tasks and seeds, each one's mean over the tasks and the difference A - B per seed (averaged
over the tasks both completed on that seed) with its interval. A cell that failed is left out and
counted. Used by studies/answers_twenty_seeds/answers-twenty-seeds.md.
"""

from __future__ import annotations

import argparse
import math
from collections import defaultdict
from pathlib import Path

import numpy as np
from scipy import stats

from novelty.bench.results import read_rows

#: the interval's level
LEVEL = 0.95


def interval(values) -> tuple[float, float, float, float]:
    """``(mean, sd, low, high)`` of ``values``: the mean's t interval at :data:`LEVEL` (NaN ends below two values)."""
    v = np.asarray(values, dtype=np.float64)
    mean = float(v.mean())
    if v.size < 2:
        return mean, math.nan, math.nan, math.nan
    sd = float(v.std(ddof=1))
    half = float(stats.t.ppf(0.5 + LEVEL / 2, v.size - 1)) * sd / math.sqrt(v.size)
    return mean, sd, mean - half, mean + half


def where(low: float, high: float) -> str:
    """Where an interval lies against chance (0.5)."""
    if low > 0.5:
        return "above chance"
    if high < 0.5:
        return "below chance"
    return "at chance"


def cells(rows) -> tuple[dict, dict]:
    """``{(detector, task): {seed: ROC AUC}}`` of the cells that are ok, and ``{(detector, task): failed}``."""
    ok, failed = defaultdict(dict), defaultdict(int)
    for r in rows:
        key = (r["detector"], r["task"])
        if r.get("status") == "ok" and r.get("roc_auc") is not None and math.isfinite(float(r["roc_auc"])):
            ok[key][int(r["seed"])] = float(r["roc_auc"])
        else:
            failed[key] += 1
    return dict(ok), dict(failed)


def margins(rows) -> list[dict]:
    """One record per detector and task, sorted by detector, then task."""
    ok, failed = cells(rows)
    out = []
    for (det, task), by_seed in sorted(ok.items()):
        mean, sd, low, high = interval(list(by_seed.values()))
        out.append({"detector": det, "task": task, "n": len(by_seed), "failed": failed.get((det, task), 0),
                    "mean": mean, "sd": sd, "low": low, "high": high,
                    "at_or_below": sum(v <= 0.5 for v in by_seed.values()), "where": where(low, high)})
    return out


def paired(rows, a: str, b: str) -> dict:
    """Each detector's mean over the tasks, and the per-seed difference ``a - b`` (over the tasks both did)."""
    ok, _ = cells(rows)
    tasks = sorted({t for d, t in ok if d == a} & {t for d, t in ok if d == b})
    if not tasks:
        raise ValueError(f"{a} and {b} share no task with results.")
    seeds = sorted({s for t in tasks for s in ok[(a, t)]} & {s for t in tasks for s in ok[(b, t)]})
    diffs = []
    for s in seeds:
        both = [t for t in tasks if s in ok[(a, t)] and s in ok[(b, t)]]
        diffs.append(np.mean([ok[(a, t)][s] - ok[(b, t)][s] for t in both]))
    mean_a = float(np.mean([np.mean(list(ok[(a, t)].values())) for t in tasks]))
    mean_b = float(np.mean([np.mean(list(ok[(b, t)].values())) for t in tasks]))
    mean, sd, low, high = interval(diffs)
    return {"a": a, "b": b, "tasks": len(tasks), "seeds": len(seeds), "mean_a": mean_a, "mean_b": mean_b,
            "difference": mean, "sd": sd, "low": low, "high": high}


def table(records) -> str:
    lines = ["| detector | task | seeds | mean ROC AUC | sd | 95 % interval | seeds <= 0.5 | where |",
             "|---|---|---|---|---|---|---|---|"]
    for r in records:
        seeds = f"{r['n']}" + (f" ({r['failed']} failed)" if r["failed"] else "")
        lines.append(f"| `{r['detector']}` | `{r['task']}` | {seeds} | {r['mean']:.3f} | {r['sd']:.3f} | "
                     f"{r['low']:.3f} - {r['high']:.3f} | {r['at_or_below']} | {r['where']} |")
    return "\n".join(lines)


def _rows(folders) -> list[dict]:
    rows = []
    for folder in folders:
        found = read_rows(Path(folder))
        if not found:
            raise SystemExit(f"{folder}: no rows (is it a run's folder, with results.jsonl?).")
        rows += found
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="the runs' folders")
    parser.add_argument("--pair", nargs=2, metavar=("A", "B"), help="two detectors compared seed by seed")
    args = parser.parse_args(argv)
    rows = _rows(args.runs)
    print(table(margins(rows)))
    if args.pair:
        p = paired(rows, *args.pair)
        print(f"\n{p['a']} {p['mean_a']:.3f}, {p['b']} {p['mean_b']:.3f} over {p['tasks']} tasks; "
              f"{p['a']} - {p['b']} per seed ({p['seeds']} seeds): {p['difference']:+.3f} "
              f"(95 % interval {p['low']:+.3f} to {p['high']:+.3f})")


if __name__ == "__main__":
    main()
