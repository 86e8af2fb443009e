"""Why a habituating map fails the detection guard: door G on paper-a-to-b, the open door on paper-a-to-a-star.

    taskset -c 1 python studies/maps/guard_trace.py                       # the defaults, seeds 105-109
    taskset -c 1 python studies/maps/guard_trace.py --param tolerance=0 --param unseen=0.25

The guard (benchmarks/suites/maps-detection.toml) gives ``habituating-map`` the simulated sonar ring's 16
echoes in the world (the ``points`` input). On each seed the map learns the task's training part and
scores its test part (as the hold-out protocol does); every test scan is traced to its most novel hit
cell (``v`` as the map explains it: HabituatingMap.explain, equation 1 of novelty/maps/cells.py).

``paper-a-to-b`` (learn corridor A, patrol B; door G, inset 0.35 m, labelled novel; the corridor's
right wall on y = 0, its left on y = 1.7 m): the most novel cell's efficacy (median) and the cells with
``v`` > 0.05 a scan, per class; of the familiar scans above the novel scans' median, the share whose
most novel cell lies more than 0.2 m behind a wall line, and at the ends of the route (x < -2 m or
> 12 m); the share of the novel scans' echoes in door G's recess (x 3.15-4.05 m, y -0.45 to -0.2 m).

``paper-a-to-a-star`` (A with the door on the right at 3 m opened onto an office): the labelled scans
with no echo beyond the doorway (x 2.5-3.5 m, y < -0.25 m), the share of those echoes in cells no ray
crossed in training (``f`` = 0: scored 0 by (2) with ``unseen`` = 0), and the novel scans at or below
the familiar scans' median.

Every guard task with poses (``--saturation``): the share of familiar and of novel test scans the map
scores at ``SATURATED`` (0.99) or more, as new as a scan can be. Where the patrolled corridor is another
place than the learned one (B's doors stand 0.2-0.8 m from A's; C is another corridor), a map of places
scores most familiar scans there: the task's labels name a feature (door G), the map a place.

Development seeds only: the guard's reported seeds 5-9 and the objects' 0-4 are refused.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from novelty.bench.holdout.metrics import roc_auc
from novelty.maps import HabituatingMap, habituating_map, split_points
from novelty.registry import of_kind

REPORTED = range(0, 10)
FAR = 0.2          # m behind a wall line
BEHIND = 0.25      # m behind the right wall: beyond the doorway
DOOR_G = (3.15, 4.05, -0.45, -0.2)
#: a scan's novelty at or above this is saturated: as new as the map can say
SATURATED = 0.99
GUARD_TASKS = ("paper-a-to-a-star", "paper-a-to-b", "paper-a-to-c", "inspection-easy", "inspection-medium",
               "inspection-hard")


def _value(text: str):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def top_cells(det: HabituatingMap, X: np.ndarray) -> np.ndarray:
    """Per scan: (v, efficacy as read, passes, x, y of the centre) of its most novel hit cell; the count of v > 0.05
    (each scan as the map explains it: HabituatingMap.explain)."""
    out = []
    for x in X:
        e = det.explain(x)
        v = e["novelty"]
        k = int(np.argmax(v))
        out.append((v[k], e["efficacy"][k], e["passes"][k], *e["centres"][k], float(np.sum(v > 0.05))))
    return np.array(out)


def door_g(params: dict, seeds) -> None:
    rows, aucs, in_recess = [], [], []
    for seed in seeds:
        data = of_kind("dataset").make("paper-a-to-b", seed=seed, inputs="points")
        train, test = data.train(), data.test()
        det = habituating_map(**params).fit(train.X)
        y = test.y.astype(bool)
        aucs.append(roc_auc(det.novelty(test.X), y))
        t = top_cells(det, test.X)
        rows.append(np.c_[t, det.novelty(test.X), y])
        _, near, ends = split_points(test.X[y])
        e = ends[near > 0]
        x0, x1, y0, y1 = DOOR_G
        in_recess.append(np.mean((e[:, 0] > x0) & (e[:, 0] < x1) & (e[:, 1] > y0) & (e[:, 1] < y1)))
    r = np.vstack(rows)
    novel = r[:, 7] == 1
    above = ~novel & (r[:, 6] > np.median(r[novel, 6]))
    lat, x = r[above, 4], r[above, 3]
    print(f"paper-a-to-b: ROC AUC {np.mean(aucs):.3f} ({' '.join(f'{a:.3f}' for a in aucs)})")
    for name, m in (("novel", novel), ("familiar", ~novel)):
        print(f"  {name} scans {m.sum()}: most novel cell's efficacy (median) {np.median(r[m, 1]):.3f}; "
              f"cells with v > 0.05 a scan {r[m, 5].mean():.2f}")
    print(f"  familiar scans above the novel median: {above.sum()}; their most novel cell behind a wall line "
          f"(> {FAR} m) {np.mean((lat < -FAR) | (lat > 1.7 + FAR)):.2f}, at the route's ends "
          f"{np.mean((x < -2) | (x > 12)):.2f}")
    print(f"  novel scans' echoes in door G's recess: {np.mean(in_recess):.3f} (per seed "
          f"{' '.join(f'{a:.3f}' for a in in_recess)})")


def open_door(params: dict, seeds) -> None:
    rows, aucs = [], []
    for seed in seeds:
        data = of_kind("dataset").make("paper-a-to-a-star", seed=seed, inputs="points")
        train, test = data.train(), data.test()
        det = habituating_map(**params).fit(train.X)
        s, y = det.novelty(test.X), test.y.astype(bool)
        aucs.append(roc_auc(s, y))
        poses, near, ends = split_points(test.X)
        for i in np.flatnonzero(y):
            e = ends[i][near[i] > 0]
            room = e[(e[:, 0] > 2.5) & (e[:, 0] < 3.5) & (e[:, 1] < -BEHIND)]
            f = det.read_cells(np.floor(room / det.clusterer.cell_size))["passes"]
            rows.append((len(room), int(np.sum(f == 0)), s[i] <= np.median(s[~y])))
    r = np.array(rows, dtype=float)
    print(f"paper-a-to-a-star: ROC AUC {np.mean(aucs):.3f} ({' '.join(f'{a:.3f}' for a in aucs)})")
    print(f"  labelled scans {len(r)}: with no echo beyond the doorway {np.mean(r[:, 0] == 0):.2f}; of the echoes "
          f"beyond it, in cells never crossed in training {r[:, 1].sum() / max(r[:, 0].sum(), 1):.2f}; "
          f"at or below the familiar median {r[:, 2].mean():.2f}")


def saturated_shares(novelty: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """The share of familiar (``y`` 0) and of novel (``y`` 1) scans with novelty >= SATURATED (NaN: none)."""
    novelty, y = np.asarray(novelty, dtype=float), np.asarray(y).astype(bool)
    at = novelty >= SATURATED
    share = [float(at[m].mean()) if m.any() else float("nan") for m in (~y, y)]
    return share[0], share[1]


def saturation(params: dict, seeds) -> None:
    for task in GUARD_TASKS:
        rows = []
        for seed in seeds:
            data = of_kind("dataset").make(task, seed=seed, inputs="points")
            train, test = data.train(), data.test()
            s = habituating_map(**params).fit(train.X).novelty(test.X)
            rows.append((roc_auc(s, test.y.astype(bool)), *saturated_shares(s, test.y)))
        auc, familiar, novel = np.mean(rows, axis=0)
        print(f"  {task}: ROC AUC {auc:.3f}; scans at novelty >= {SATURATED}: familiar {familiar:.2f}, "
              f"novel {novel:.2f}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(105, 110)))
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="a parameter of habituating-map (repeat); its defaults otherwise")
    parser.add_argument("--saturation", action="store_true",
                        help="every guard task: the share of familiar and novel scans scored as new as can be")
    args = parser.parse_args(argv)
    if any(s in REPORTED for s in args.seeds):
        sys.exit("guard_trace: seeds 0-9 are reported seeds; trace on development seeds (105-109).")
    params = {k: _value(v) for k, v in (p.split("=", 1) for p in args.param)}
    print(f"habituating-map {params or '(defaults)'}, seeds {args.seeds}")
    if args.saturation:
        saturation(params, args.seeds)
        return
    door_g(params, args.seeds)
    open_door(params, args.seeds)


if __name__ == "__main__":
    main()
