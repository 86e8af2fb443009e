"""Why a habituating map, learning as it drives, does not flag first sight: which familiar scans outrank it.

    NOVELTY_DATA_DIR=/data taskset -c 1 python studies/maps/diagnosis.py --seeds 100 101 102 103 104
    NOVELTY_DATA_DIR=/data taskset -c 1 python studies/maps/diagnosis.py --param tolerance=0   # as in the guide

On the exploration tasks with objects (``exploration-objects-radish-*``, the ``points`` input with 180
sectors), every scan is scored by ``habituating-map`` (its defaults, or ``--param name=value``) before it
is learned, as the exploration protocol does, and each score is traced to the cells that make it: the
``top`` hit cells with the largest novelty ``v = y (u + (1 - u) (1 - exp(-f / f0)))`` (HabituatingMap.explain, novelty/maps/cells.py;
``y`` read with the map's ``tolerance``, ``u`` its ``unseen``, ``v`` = 0 below its ``min_passes``).

The first-encounter ROC AUC compares the first sights (scans at an object's first pass) with the familiar
scans of the same runs. Its shortfall ``1 - AUC`` is the share of (first sight, familiar scan) pairs in
which the familiar scan scores higher (ties count half), so it splits exactly over the familiar scans: each
carries the pairs it wins. Each familiar scan is put in the first of these classes that holds:

1. ``object edge``: one of its scoring cells holds an echo off an object (the object seen on fewer beams
   than the label's three, or from a scan labelled for another object);
2. ``first visit``: the robot stands where it never stood before (no earlier pose within 1 m facing within
   90 degrees: novelty.tasks.objects.object_tasks.familiar_places): a place first met;
3. ``one cell off a known surface, along the beam``: every scoring cell has a cell hit before next to it
   along the beam from the robot (the cell half a cell nearer or farther along the ray through its
   centre): a surface the map knows, its echo landing short or long (range noise, pose error);
4. ``beside a known surface``: every scoring cell borders a cell hit before (one of its eight neighbours),
   not all along the beam: a known surface seen on a new stretch, or from an angle that moves its echo
   sideways (grazing rays, heading error);
5. ``evidence only recent``: every scoring cell was seen through only in the last 20 scans (the same
   stretch of the drive), never on an earlier pass;
6. ``other``.

A scoring cell is one of the ``top`` whose ``v`` > 0. Beside the classes, the flags (not exclusive): the
robot turned by more than 0.1 rad since its previous scan; a scoring cell lies more than 3 m away; a
scoring cell was seen through at most twice. Each flag's share among the familiar scans that outrank the
median first sight is set beside its share among all of them (a cause is over-represented where it acts).

The first sights are traced too: the share whose object cells were never seen through before (``f`` = 0:
an object where the robot had seen no free space scores 0 with ``evidence="free"``, by design) and the
share whose object cells were already habituated (``y`` < 0.9: hit by earlier scans that saw the object
on fewer beams than the label's count), and the share whose object cells had been seen through before
the object appeared (the object stands where the robot had seen free space: a change of a place it
knew; otherwise a first sight is also the first sight of a place).

Reads the Radish logs from ``--data`` or ``$NOVELTY_DATA_DIR`` (never copies them). Development seeds
only: the reported seeds 0-4 are refused.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import defaultdict

import numpy as np

from novelty.bench.holdout.metrics import roc_auc
from novelty.data import FAMILIAR
from novelty.tasks.objects import cast_all
from novelty.tasks.objects.placement import object_from_fields
from novelty.tasks.radish import radish_objects_exploration
from novelty.tasks.objects.object_tasks import LABEL_DEFAULTS, familiar_places, read_drive
from novelty.tasks.radish import radish_log
from novelty.maps import HabituatingMap, habituating_map, split_points
from novelty.maps.habituating_map import cell_keys

#: a cell's eight neighbours
NEIGHBOURS = np.array([(di, dj) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj])

REPORTED = range(0, 5)
CLASSES = ("object edge", "first visit", "one cell off a known surface, along the beam",
           "beside a known surface", "evidence only recent", "other")
FLAGS = ("turning", "far", "few passes")
RECENT = 20        # scans: the stretch of a run
TURN = 0.1         # rad between scans
FAR = 3.0          # m
FEW = 2            # passes
ON_OBJECT = 0.02   # m: an end point this close to an object's surface is its echo


def trace(det: HabituatingMap, X: np.ndarray, objects, times) -> dict:
    """Score and learn every scan as ``det.stream`` does, keeping what makes each score.

    Each scan is read as the map explains it (``HabituatingMap.explain``: its hit cells, their ``v``, the
    ones that make its score) before it is learned; the scores are checked against ``stream`` by the caller.
    """
    poses, near, ends = split_points(X)
    c = float(det.clusterer.cell_size)
    first_crossed = {}
    # the scan at which the first object appears (they all appear together in these tasks)
    appeared = int(np.searchsorted(times, min(o.start for o in objects))) if objects else len(X)
    out = defaultdict(list)
    for i in range(len(X)):
        e = det.explain(X[i])
        hits, f, own, scoring = pack(e["cells"]), e["passes"], e["own_efficacy"], e["scoring"]
        cells, centres = e["cells"][scoring], e["centres"][scoring]
        fitted = hasattr(det, "clusterer_")
        bordered, along = np.zeros(cells.shape[0], dtype=bool), np.zeros(cells.shape[0], dtype=bool)
        if fitted and cells.size:
            # a cell hit before: its synapse below a fresh one's
            around = (cells[:, None, :] + NEIGHBOURS[None, :, :]).reshape(-1, 2)
            bordered = (det.read_cells(around)["efficacy"] < 1.0).reshape(cells.shape[0], -1).any(axis=1)
            ray = centres - poses[i, :2]
            unit = ray / np.maximum(np.hypot(*ray.T), 1e-9)[:, None]
            ahead = np.concatenate([np.floor((centres + sign * 0.75 * c * unit) / c) for sign in (-1, 1)])
            along = (det.read_cells(ahead)["efficacy"] < 1.0).reshape(2, -1).any(axis=0)
        # the cells holding an echo off an object standing at this scan's time
        hit_ends = ends[i][near[i] > 0]
        object_keys = np.empty(0, dtype=np.int64)
        for obj in objects:
            if not obj.present(np.array([times[i]]))[0] or hit_ends.size == 0:
                continue
            on = np.hypot(*(obj.closest(hit_ends) - hit_ends).T) < ON_OBJECT
            if on.any():
                object_keys = np.union1d(object_keys, np.unique(cell_keys(hit_ends[on], c)))
        on_object = np.isin(hits, object_keys)
        keys = hits[scoring]
        out["score"].append(e["score"])
        out["top_on_object"].append(bool(on_object[scoring].any()))
        out["top_along"].append(bool(keys.size) and bool(along.all()))
        out["top_bordered"].append(bool(keys.size) and bool((bordered | along).all()))
        out["top_recent"].append(bool(keys.size) and all(first_crossed.get(int(q), -1) >= i - RECENT for q in keys))
        out["top_far"].append(bool(keys.size) and bool((np.hypot(*(centres - poses[i, :2]).T) > FAR).any()))
        out["top_few"].append(bool(keys.size) and bool((f[scoring] <= FEW).any()))
        out["object_cells"].append(int(on_object.sum()))
        out["object_unseen"].append(bool(on_object.any()) and bool((f[on_object] == 0).all()))
        out["object_habituated"].append(bool(on_object.any()) and bool((own[on_object] < 0.9).any()))
        out["object_known"].append(bool(on_object.any()) and any(
            first_crossed.get(int(q), len(X)) < appeared for q in hits[on_object]))
        for q in pack(e["passed"]).tolist():
            first_crossed.setdefault(q, i)
        det.partial_fit(X[i:i + 1])
    out = {name: np.asarray(values) for name, values in out.items()}
    turn = np.abs((np.diff(poses[:, 2], prepend=poses[0, 2]) + np.pi) % (2 * np.pi) - np.pi)
    out["turning"] = turn > TURN
    out["first_visit"] = np.array([i > 0 and not familiar_places(poses[i], poses[:i])[0] for i in range(len(X))])
    return out


def pack(cells: np.ndarray) -> np.ndarray:
    """Cells (i, j) as one int64 each (cell_keys of their centres)."""
    return cell_keys(np.asarray(cells, dtype=np.float64) + 0.5, 1.0)


def classify(t: dict) -> np.ndarray:
    """Each scan's class (index into CLASSES), the first that holds (module docstring)."""
    tests = [t["top_on_object"], t["first_visit"], t["top_along"], t["top_bordered"], t["top_recent"],
             np.ones(len(t["score"]), dtype=bool)]
    return np.argmax(np.stack(tests), axis=0)


def pair_losses(scores, first, familiar) -> np.ndarray:
    """For each familiar scan, the first sights it outranks (ties half): the pairs it costs the AUC."""
    pos = np.sort(scores[first])
    s = scores[familiar]
    below = np.searchsorted(pos, s, side="left")
    tied = np.searchsorted(pos, s, side="right") - below
    return below + 0.5 * tied


def diagnose(log: str, seed: int, params: dict, path=None, options: dict | None = None) -> dict:
    task = radish_objects_exploration(log, path, seed, **{"inputs": "points", "sectors": 180, **(options or {})})
    objects = [object_from_fields(dict(o)) for o in task.metadata["objects"]]
    det = habituating_map(**params)
    t = trace(det, task.X, objects, task.columns["time"])
    streamed = habituating_map(**params).stream(task.X)
    if not np.allclose(streamed, t["score"], atol=1e-12):
        raise AssertionError("the trace does not reproduce the detector's scores")
    sweeps = read_drive(radish_log(log, path))
    cast = cast_all(sweeps, objects, margin=LABEL_DEFAULTS["margin"], within=task.metadata["threshold_m"])
    warm = int(task.metadata["exploration"]["warmup_runs"])
    run, feature = np.asarray(task.run), task.columns["feature"].astype(str)
    exposure = np.asarray(task.columns["exposure"])
    scored = run >= warm
    first = scored & (exposure == 0) & (feature != FAMILIAR)
    familiar = scored & (feature == FAMILIAR) & np.isin(run, np.unique(run[first]))
    scores = t["score"]
    losses = pair_losses(scores, first, familiar)
    pairs = first.sum() * familiar.sum()
    cls = classify(t)[familiar]
    above = scores[familiar] > np.median(scores[first])
    below_label = (cast.shortened[familiar] > 0).any(axis=1)
    row = {"log": log, "seed": seed, "auc": 1 - losses.sum() / pairs, "n_first": int(first.sum()),
           "n_familiar": int(familiar.sum()), "n_above": int(above.sum()),
           "first_zero": float(np.mean(scores[first] == 0)),
           "first_unseen": float(np.mean(t["object_unseen"][first])),
           "first_habituated": float(np.mean(t["object_habituated"][first])),
           "first_known": float(np.mean(t["object_known"][first])),
           "first_median": float(np.median(scores[first])), "familiar_median": float(np.median(scores[familiar])),
           "below_label_above": int((below_label & above).sum()), "below_label": int(below_label.sum())}
    # first sights of a place seen through before the object appeared, and of a place first seen with it
    known = t["object_known"]
    for part, mine in (("known", first & known), ("new", first & ~known)):
        keep = mine | familiar
        row[f"auc_{part}"] = float(roc_auc(scores[keep], mine[keep])) if mine.any() else float("nan")
        row[f"n_{part}"] = int(mine.sum())
    # the first scan of each object's first pass against the later scans of that pass
    objects_seen = task.columns["object"].astype(str)
    leading = np.zeros(len(scores), dtype=bool)
    for name in np.unique(objects_seen[first]):
        leading[np.flatnonzero(first & (objects_seen == name))[0]] = True
    row.update(first_pass_scans=float(first.sum() / max(leading.sum(), 1)),
               leading_median=float(np.median(scores[leading])),
               later_median=float(np.median(scores[first & ~leading])) if (first & ~leading).any() else float("nan"))
    for j, name in enumerate(CLASSES):
        mine = cls == j
        row[f"loss:{name}"] = float(losses[mine].sum() / pairs)
        row[f"above:{name}"] = int((mine & above).sum())
        row[f"all:{name}"] = int(mine.sum())
    for name, key in zip(FLAGS, ("turning", "top_far", "top_few")):
        flag = t[key][familiar]
        row[f"flag_above:{name}"] = int((flag & above).sum())
        row[f"flag_all:{name}"] = int(flag.sum())
    return row


def _total(rows: list[dict]):
    return lambda key: sum(r[key] for r in rows)


def _mean(rows: list[dict]):
    return lambda key: float(np.mean([r[key] for r in rows]))


def report(rows: list[dict]) -> str:
    lines = ["| log | seeds | AUC | 1 - AUC | " + " | ".join(CLASSES) + " |", "|---" * (4 + len(CLASSES)) + "|"]
    for log in dict.fromkeys(r["log"] for r in rows):
        mine = [r for r in rows if r["log"] == log]
        auc = np.mean([r["auc"] for r in mine])
        share = [np.mean([r[f"loss:{c}"] for r in mine]) for c in CLASSES]
        lines.append(f"| {log} | {len(mine)} | {auc:.3f} | {1 - auc:.3f} | "
                     + " | ".join(f"{s:.3f} ({s / max(1 - auc, 1e-12):.0%})" for s in share) + " |")
    lines += ["", "Familiar scans above the median first sight, by class (count / of all familiar scans in the class):", "",
              "| log | above / familiar | " + " | ".join(CLASSES) + " |", "|---" * (2 + len(CLASSES)) + "|"]
    for log in dict.fromkeys(r["log"] for r in rows):
        mine = [r for r in rows if r["log"] == log]
        tot = _total(mine)
        lines.append(f"| {log} | {tot('n_above')} / {tot('n_familiar')} | " + " | ".join(
            f"{tot('above:' + c)} / {tot('all:' + c)}" for c in CLASSES) + " |")
    lines += ["", "Flags (not exclusive): share among the familiar scans above the median first sight, and among all:", "",
              "| log | " + " | ".join(FLAGS) + " | fewer beams than the label (above / all) |", "|---" * (2 + len(FLAGS)) + "|"]
    for log in dict.fromkeys(r["log"] for r in rows):
        mine = [r for r in rows if r["log"] == log]
        tot = _total(mine)
        cells = [f"{tot('flag_above:' + f) / max(tot('n_above'), 1):.0%} / {tot('flag_all:' + f) / tot('n_familiar'):.0%}"
                 for f in FLAGS]
        lines.append(f"| {log} | " + " | ".join(cells) + f" | {tot('below_label_above')} / {tot('below_label')} |")
    lines += ["", "First sights where the robot had seen free space before the object appeared, and the others, each "
              "against the same familiar scans (first-encounter AUC, mean over the seeds that have them; scans):", "",
              "| log | place seen before | place first seen with the object |", "|---|---|---|"]
    for log in dict.fromkeys(r["log"] for r in rows):
        mine = [r for r in rows if r["log"] == log]
        cells = [f"{np.nanmean([r['auc_' + p] for r in mine]):.3f} ({sum(r['n_' + p] for r in mine)})"
                 for p in ("known", "new")]
        lines.append(f"| {log} | " + " | ".join(cells) + " |")
    lines += ["", "First sights (mean over seeds):", "",
              "| log | first sights | scans a first pass | median score: first scan of the pass / later ones / familiar "
              "| scored 0 | object cells never seen through | object cells already habituated "
              "| object cells seen through before it appeared |", "|---" * 8 + "|"]
    for log in dict.fromkeys(r["log"] for r in rows):
        mine = [r for r in rows if r["log"] == log]
        m = _mean(mine)
        lines.append(f"| {log} | {sum(r['n_first'] for r in mine)} | {m('first_pass_scans'):.1f} | "
                     f"{m('leading_median'):.3f} / {np.nanmean([r['later_median'] for r in mine]):.3f} / "
                     f"{m('familiar_median'):.3f} | {m('first_zero'):.0%} | {m('first_unseen'):.0%} | "
                     f"{m('first_habituated'):.0%} | {m('first_known'):.0%} |")
    return "\n".join(lines)


def _param(text: str):
    name, _, value = text.partition("=")
    try:
        return name, json.loads(value)
    except json.JSONDecodeError:
        return name, value


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--logs", nargs="+", default=["intel", "aces", "csail"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[100, 101, 102, 103, 104])
    parser.add_argument("--data", default=None, help="the folder of the Radish logs (default $NOVELTY_DATA_DIR)")
    parser.add_argument("--param", action="append", default=[], help="a HabituatingMap parameter, name=value")
    parser.add_argument("--option", action="append", default=[],
                        help="an option of the task (exploration_task), name=value; e.g. seen_before=1")
    parser.add_argument("--json", default=None, help="write the per-task rows here")
    args = parser.parse_args(argv)
    if any(s in REPORTED for s in args.seeds):
        parser.error("seeds 0-4 are the reported seeds: diagnose on development seeds (100-104).")
    params = dict(_param(p) for p in args.param)
    options = dict(_param(p) for p in args.option)
    rows = []
    for log in args.logs:
        for seed in args.seeds:
            rows.append(diagnose(log, seed, params, args.data, options))
            print(f"{log} seed {seed}: AUC {rows[-1]['auc']:.3f}", file=sys.stderr)
    print(report(rows))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
