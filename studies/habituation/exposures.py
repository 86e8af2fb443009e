"""The exposures behind a 3rd/1st excess: per object, its scans, its novelty and its run's familiar level.

    python studies/habituation/exposures.py results/habituation-development-seen --detector defaults \
        --task exploration-objects-radish-intel-familiar

Reads the per-scan arrays ``novelty bench`` keeps for each cell (``cells/<cell_id>.npz``: the novelty, run,
feature and exposure of every scan, and the per-object curves of
:mod:`novelty.bench.exploration.metrics`) and prints, one line an object met at least three times (a
recurring feature, the ones the 3rd/1st excess averages over), for its 1st, 2nd and 3rd exposure: the scans
that saw it, their mean novelty, the familiar level of the run they fell in and the excess (the difference);
then, over those objects, the spread of the familiar levels and how many 3rd exposures rest on one or two
scans.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from novelty.bench.exploration.metrics import RECURRING


def exposures(cell: dict[str, np.ndarray], seed: int) -> list[dict]:
    """One record per recurring object of a cell's arrays: seed, feature, and per exposure (1st to
    :data:`RECURRING`-th) its scans, novelty, familiar level and excess."""
    out = []
    for i, feature in enumerate(cell["curve_features"]):
        excess = cell["curve_excess"][i][:RECURRING]
        if excess.size < RECURRING or np.isnan(excess).any():
            continue
        mine = cell["feature"] == feature
        scans = [int(np.sum(mine & (cell["exposure"] == k))) for k in range(RECURRING)]
        out.append({"seed": seed, "feature": str(feature), "scans": scans,
                    "novelty": cell["curve_novelty"][i][:RECURRING].tolist(),
                    "familiar": cell["curve_familiar"][i][:RECURRING].tolist(), "excess": excess.tolist()})
    return out


def read_cells(run: Path, detector: str, task: str) -> list[dict]:
    """The recurring objects of every seed of ``detector`` on ``task`` in a run folder (its results.jsonl
    and cells/)."""
    records = []
    with open(run / "results.jsonl", encoding="utf-8") as fh:
        rows = [json.loads(line) for line in fh if line.strip()]
    for row in sorted((r for r in rows if r["detector"] == detector and r["task"] == task), key=lambda r: r["seed"]):
        with np.load(run / "cells" / f"{row['cell_id']}.npz", allow_pickle=False) as cell:
            records += exposures(dict(cell), int(row["seed"]))
    return records


def summary(records: list[dict]) -> dict:
    """Over the objects: how many, the mean novelty, familiar level and excess per exposure, the familiar levels'
    range, the 3rd exposures on one or two scans and their share of the summed 3rd excess."""
    excess = np.array([r["excess"] for r in records])
    familiar = np.array([r["familiar"] for r in records])
    novelty = np.array([r["novelty"] for r in records])
    thin = np.array([r["scans"][RECURRING - 1] <= 2 for r in records])
    third = excess[:, RECURRING - 1]
    return {"objects": len(records), "mean_excess": excess.mean(axis=0).tolist(),
            "mean_novelty": novelty.mean(axis=0).tolist(), "mean_familiar": familiar.mean(axis=0).tolist(),
            "familiar_range": (float(familiar.min()), float(familiar.max())),
            "thin_third": int(thin.sum()),
            "thin_share": float(third[thin].sum() / third.sum()) if third.sum() else float("nan")}


def _row(r: dict) -> str:
    cells = " | ".join(f"{n} | {v:.3f} | {f:.3f} | {e:+.3f}"
                       for n, v, f, e in zip(r["scans"], r["novelty"], r["familiar"], r["excess"]))
    return f"| {r['seed']} | {r['feature']} | {cells} |"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="the run's folder, as `novelty bench --out` wrote it")
    parser.add_argument("--detector", default="defaults", help="the candidate's label")
    parser.add_argument("--task", default="exploration-objects-radish-intel-familiar", help="the task's label")
    args = parser.parse_args(argv)
    records = read_cells(args.run, args.detector, args.task)
    if not records:
        parser.error(f"no recurring object of {args.detector!r} on {args.task!r} in {args.run}")
    head = " | ".join(f"{k} scans | novelty | familiar | excess" for k in ("1st", "2nd", "3rd"))
    print(f"| seed | object | {head} |\n|" + "---|" * 14)
    print("\n".join(_row(r) for r in records))
    s = summary(records)
    mean = lambda key, sign="": " / ".join(f"{v:{sign}.3f}" for v in s[key])  # noqa: E731
    print(f"\n{s['objects']} objects; mean novelty {mean('mean_novelty')}, familiar level {mean('mean_familiar')}, "
          f"excess {mean('mean_excess', '+')}; familiar levels "
          f"{s['familiar_range'][0]:.3f}-{s['familiar_range'][1]:.3f}; {s['thin_third']} 3rd exposures on one or two "
          f"scans, {s['thin_share']:.0%} of the summed 3rd excess")


if __name__ == "__main__":
    main()
