"""Alarms at a stated false-alarm rate: what a robot gets from a calibrated threshold, per detector and task.

For each hold-out task (the Radish logs with virtual objects, the simulated
corridors), seed and detector, with the library's public API only:

1. the robot learns its familiar stretch less a held-out end: the training part
   of the task but its last quarter (at least 100 scans, so that a 1 % rate has
   a finite threshold), learned as the benchmark learns it (streamed, or fitted
   by a batch-only detector);
2. the held-out end, scans of the same familiar run that were not learned, is
   the calibration: ``det.calibrate(X_held_out, false_alarm_rate=a)``, scored
   frozen, for a = 1 % and 5 %;
3. the test part is scored frozen: the false-alarm rate is the share of its
   familiar scans (y = 0) that raise an alarm, the hits the share of its scans
   with a novelty (y = 1: a virtual object seen; a door, a new corridor) that
   raise one.

The false-alarm rate is pooled over the seeds, with its Clopper-Pearson 95 %
interval; where the target lies outside it, the later familiar scans are not
exchangeable with the calibration scans: the drift is given as the share of
the later familiar scans above the calibration scans' median (one half
without drift).

    NOVELTY_DATA_DIR=/data python studies/alarms/operating_point.py --out studies/alarms/results.csv
    python studies/alarms/operating_point.py --table studies/alarms/results.csv   # the table, as markdown

The rows are one (task, seed, detector, target): counts, so that any pooling
can be redone from them.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.stats import beta

import novelty
from novelty.datasets import load

#: the detectors measured: the answers of "Which detector?" and the baselines it names
DETECTORS = ("kmeans-stanley", "parzen", "isolation-forest", "som-distance", "nearest-memory", "hsom",
             "gwr-explore-wang-hsu", "map-explore")
#: detectors that read the robot's pose with each scan: given the points input
POINTS = ("map-explore",)
REAL = ("inspection-objects-radish-intel", "inspection-objects-radish-aces", "inspection-objects-radish-csail")
SIMULATED = ("paper-a-to-a-star", "paper-a-to-b", "paper-a-to-c", "inspection-easy", "inspection-medium",
             "inspection-hard")
TARGETS = (0.01, 0.05)
#: the held-out end of the familiar run: a quarter of it, at least this many scans
LEAST_HELD_OUT = 100
FIELDS = ("task", "seed", "detector", "target", "n_learned", "n_calibration", "threshold", "n_familiar",
          "false_alarms", "n_novel", "hits", "familiar_above_median")


def task_for(name: str, seed: int, inputs: str):
    """The task's rows of ``inputs`` (the ring, or the points input: 180 sectors of a laser)."""
    options = {"seed": seed}
    if inputs == "points":
        options.update(inputs="points", sectors=180) if name in REAL else options.update(inputs="points")
    return load(name, **options)


def split(task):
    """The learned scans, the held-out end of the familiar run, and the test part."""
    train, test = task.train(), task.test()
    held = max(LEAST_HELD_OUT, len(train) // 4)
    if held >= len(train):
        raise ValueError(f"{task.name}: {len(train)} training scans leave none to learn beside {held} held out.")
    return train.X[:-held], train.X[-held:], test, task.train_passes


def learn(detector: str, seed: int, X: np.ndarray, passes: int):
    det = novelty.make(detector)
    if "random_state" in det.get_params(deep=False):
        det.set_params(random_state=seed)
    if not det.supports_online:
        return det.fit(X)
    for _ in range(passes):
        det.partial_fit(X)
    return det


def measure(name: str, seed: int, detector: str, task) -> list[dict]:
    learned, held_out, test, passes = split(task)
    det = learn(detector, seed, learned, passes)
    novelty_test = det.novelty(test.X)
    familiar, novel = test.y == 0, test.y == 1
    rows = []
    for target in TARGETS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", novelty.conformal.CalibrationWarning)
            det.calibrate(held_out, false_alarm_rate=target, source=f"{name}, the end of its familiar run")
        alarm = det.predict(test.X) == -1
        rows.append({
            "task": name, "seed": seed, "detector": detector, "target": target, "n_learned": len(learned),
            "n_calibration": len(held_out), "threshold": det.threshold_, "n_familiar": int(familiar.sum()),
            "false_alarms": int(alarm[familiar].sum()), "n_novel": int(novel.sum()), "hits": int(alarm[novel].sum()),
            "familiar_above_median": int((novelty_test[familiar] > np.median(det.familiar_scores_)).sum()),
        })
    return rows


def run(tasks, seeds, detectors, out: Path) -> None:
    done = set()
    if out.exists():
        with open(out, newline="") as fh:
            done = {(r["task"], int(r["seed"]), r["detector"]) for r in csv.DictReader(fh)}
    new = not out.exists()
    with open(out, "a", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=FIELDS, lineterminator="\n")
        if new:
            writer.writeheader()
        for name in tasks:
            for seed in seeds:
                built = {}   # the task's rows of each input, read once for every detector
                for detector in detectors:
                    if (name, seed, detector) in done:
                        continue
                    start = time.perf_counter()
                    inputs = "points" if detector in POINTS else "ring"
                    if inputs not in built:
                        built[inputs] = task_for(name, seed, inputs)
                    for row in measure(name, seed, detector, built[inputs]):
                        writer.writerow(row)
                    fh.flush()
                    print(f"{name} seed {seed} {detector}: {time.perf_counter() - start:.1f} s", file=sys.stderr)


# ------------------------------------------------------------------ the table
def interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Clopper-Pearson interval of a binomial proportion k / n."""
    a = (1 - level) / 2
    low = 0.0 if k == 0 else float(beta.ppf(a, k, n - k + 1))
    high = 1.0 if k == n else float(beta.ppf(1 - a, k + 1, n - k))
    return low, high


def pooled(rows: list[dict]) -> dict:
    n, k = sum(int(r["n_familiar"]) for r in rows), sum(int(r["false_alarms"]) for r in rows)
    novel, hits = sum(int(r["n_novel"]) for r in rows), sum(int(r["hits"]) for r in rows)
    above = sum(int(r["familiar_above_median"]) for r in rows)
    return {"rate": k / n, "interval": interval(k, n), "hits": hits / novel if novel else float("nan"),
            "above": above / n, "n": n, "novel": novel, "seeds": len({r["seed"] for r in rows})}


def cell(p: dict, target: float) -> str:
    low, high = p["interval"]
    within = low <= target <= high
    text = f"{100 * p['rate']:.1f} ({100 * low:.1f}-{100 * high:.1f}){'' if within else ' *'}"
    return f"{text} / {100 * p['hits']:.0f}"


def table(path: Path, tasks) -> str:
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    detectors = list(dict.fromkeys(r["detector"] for r in rows))
    lines = []
    for target in TARGETS:
        shown = [t for t in tasks if any(r["task"] == t for r in rows)]
        lines += [f"**Target {100 * target:g} %**: false alarms on later familiar scans, % (95 % interval; * the "
                  "target outside it) / hits, % of the scans with a novelty", "",
                  "| detector | " + " | ".join(_short(t) for t in shown) + " |",
                  "| --- |" + " ---: |" * len(shown)]
        for d in detectors:
            cells = []
            for t in shown:
                these = [r for r in rows if r["task"] == t and r["detector"] == d and float(r["target"]) == target]
                cells.append(cell(pooled(these), target) if these else "-")
            lines.append(f"| `{d}` | " + " | ".join(cells) + " |")
        lines.append("")
    drift = ["**Drift**: the share of later familiar scans above the median of the calibration scans, % (50 "
             "without drift)", "", "| detector | " + " | ".join(_short(t) for t in shown) + " |",
             "| --- |" + " ---: |" * len(shown)]
    for d in detectors:
        cells = []
        for t in shown:
            these = [r for r in rows if r["task"] == t and r["detector"] == d and float(r["target"]) == TARGETS[0]]
            cells.append(f"{100 * pooled(these)['above']:.0f}" if these else "-")
        drift.append(f"| `{d}` | " + " | ".join(cells) + " |")
    return "\n".join(lines + drift) + "\n"


#: the groups of tasks of the guide's table: what "later familiar scans" are in each
GROUPS = {
    "the Radish logs with virtual objects": REAL,
    "simulated, the same corridor again": ("paper-a-to-a-star", "inspection-easy", "inspection-medium",
                                           "inspection-hard"),
    "simulated, another corridor (B, C)": ("paper-a-to-b", "paper-a-to-c"),
}
#: committed benchmark results with each detector's frozen ROC AUC: the ring's detection suite, the maps'
AUC_SUITES = ("detection", "maps-detection")
ROOT = Path(__file__).resolve().parents[2]


def roc_auc(detector: str) -> float | None:
    """The detector's mean ROC AUC over the tasks of the detection suite (the maps': its own), seeds averaged."""
    for suite in AUC_SUITES:
        with open(ROOT / "benchmarks" / "results" / suite / "results.csv", newline="") as fh:
            rows = [r for r in csv.DictReader(fh) if r["detector"] == detector and r["status"] == "ok"]
        if rows:
            tasks = sorted({r["task"] for r in rows})
            return float(np.mean([np.mean([float(r["roc_auc"]) for r in rows if r["task"] == t]) for t in tasks]))
    return None


def operating_point(path: Path) -> str:
    """The guide's tables, one a target: per detector, its frozen ROC AUC and the false-alarm rate on later
    familiar scans and the hits at that target, pooled over the tasks of each group and the seeds."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    detectors = list(dict.fromkeys(r["detector"] for r in rows))
    aucs = {d: roc_auc(d) for d in detectors}
    lines = []
    for target in TARGETS:
        lines += [f"At {100 * target:g} % (false alarms on later familiar scans, % (95 % interval; * the target "
                  "outside it) / hits, % of the scans with a novelty):", "",
                  "| detector | ROC AUC | " + " | ".join(GROUPS) + " |", "| --- | ---: |" + " ---: |" * len(GROUPS)]
        for d in detectors:
            cells = [f"`{d}`", "-" if aucs[d] is None else f"{aucs[d]:.3f}"]
            for tasks in GROUPS.values():
                these = [r for r in rows if r["detector"] == d and r["task"] in tasks and float(r["target"]) == target]
                cells.append(cell(pooled(these), target) if these else "-")
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def region(name: str) -> str:
    """The text of the region ``alarms/<name>`` of a guide (its caption first), from the committed results."""
    if name != "operating-point":
        raise KeyError(f"No region alarms/{name!r}; regions: operating-point.")
    results = Path(__file__).with_name("results.csv")
    with open(results, newline="") as fh:
        seeds = sorted({int(r["seed"]) for r in csv.DictReader(fh)})
    caption = (f"*Generated by `python benchmarks/tables.py` from `studies/alarms/results.csv`: `python "
               f"studies/alarms/operating_point.py --out studies/alarms/results.csv`, with `NOVELTY_DATA_DIR` naming "
               f"your folder of the data sets; seeds {seeds[0]}-{seeds[-1]}; ROC AUC from `benchmarks/results/` "
               f"({', '.join(AUC_SUITES)}).*")
    return f"{caption}\n\n{operating_point(results)}"


def _short(task: str) -> str:
    return task.removeprefix("inspection-objects-radish-").removeprefix("inspection-")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="results CSV (appended to; cells already in it are skipped)")
    parser.add_argument("--table", type=Path, help="print the markdown tables of a results CSV, task by task")
    parser.add_argument("--tasks", default=",".join(REAL + SIMULATED))
    parser.add_argument("--seeds", default="0,1,2,3,4")
    parser.add_argument("--detectors", default=",".join(DETECTORS))
    args = parser.parse_args(argv)
    tasks = args.tasks.split(",")
    if args.table:
        print(table(args.table, tasks), end="")
        return 0
    run(tasks, [int(s) for s in args.seeds.split(",")], args.detectors.split(","), args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
