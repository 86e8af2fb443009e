"""A robot driving through a building for the first time: does its novelty fall as places recur?

The three Radish CARMEN logs (intel, aces, csail: a laser robot driving
through an office building, with poses corrected by scan matching) are read
a scan at a time, each laser scan reduced to the paper's ring (16 sectors,
the nearest echo in each, thresholded at 4 m, normalised, inverted), and
streamed through detectors that score each scan before learning it. The
corrected poses say which scans are a first visit of their place (no
earlier pose within ``--radius`` m, or only ones of the current visit) and
which revisit it (:func:`novelty.tasks.recordings.visit_counts`).

Printed: for each log and detector, the ROC AUC of novelty separating
first visits from revisits over the whole log and over its second half
(where time alone tells less), and the mean novelty by visit count; then
the same AUC for ring variants (sectors, reduction, threshold). With
``--figure`` it draws hsom's novelty on the intel robot's path.

Run: ``python examples/robot-logs/radish.py --data <folder with the three logs>``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from sklearn.metrics import roc_auc_score

import novelty
from novelty.io import Reading, read_recording
from novelty.tasks.recordings import visit_counts

LOGS = ("intel", "aces", "csail")
ONLINE = ("hsom", "hsom-mismatch", "som-wang-hsu", "gwr-explore", "gwr-novelty", "gng-stanley",
          "kmeans-stanley", "kohonen-filter", "som-distance", "nearest-memory")
BATCH = ("lof", "isolation-forest", "parzen")
BLOCK = 50   # a batch detector is refitted every BLOCK scans on all the scans before


def stream(name: str, X: np.ndarray) -> np.ndarray:
    """Each scan's novelty before it is learned (batch detectors: refitted by blocks on the scans before)."""
    det = novelty.make(name, random_state=0) if "random_state" in novelty.make(name).get_params() \
        else novelty.make(name)
    if getattr(det, "supports_online", True):
        return det.stream(X)
    out = np.ones(len(X))   # nothing familiar before the first fit, as a habituating filter's first scan
    for start in range(BLOCK, len(X), BLOCK):
        model = novelty.make(name).fit(X[:start])
        out[start:start + BLOCK] = model.novelty(X[start:start + BLOCK])
    return out


def scores(nov: np.ndarray, visits: np.ndarray) -> dict:
    first = visits == 0
    late = np.arange(len(nov)) >= len(nov) // 2
    by_visit = [nov[visits == k].mean() if np.any(visits == k) else np.nan for k in (0, 1, 2)]
    by_visit.append(nov[visits >= 3].mean() if np.any(visits >= 3) else np.nan)
    return {"auc": roc_auc_score(first, nov), "auc_late": roc_auc_score(first[late], nov[late]),
            "by_visit": by_visit}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="folder holding <log>-corrected.log.gz")
    parser.add_argument("--radius", type=float, default=1.0, help="a place: within this many metres")
    parser.add_argument("--figure", help="write hsom's novelty on the intel path to this PNG")
    parser.add_argument("--variants", action="store_true", help="also compare ring variants")
    args = parser.parse_args(argv)
    folder = Path(args.data)
    print("| log | detector | AUC first vs revisit | AUC, second half | novelty at visit 0 / 1 / 2 / 3+ |")
    print("| --- | --- | ---: | ---: | --- |")
    for log in LOGS:
        data = read_recording(folder / f"{log}-corrected.log.gz")
        visits = visit_counts(data.poses, args.radius)
        order = 1.0 - np.arange(len(data)) / len(data)          # the control: novelty falling with time alone
        for name, nov in [("time alone (control)", order)] + [(n, stream(n, data.X)) for n in ONLINE + BATCH]:
            s = scores(nov, visits)
            print(f"| {log} | {name} | {s['auc']:.3f} | {s['auc_late']:.3f} | "
                  + " / ".join("-" if np.isnan(v) else f"{v:.3f}" for v in s["by_visit"]) + " |")
        counts = np.bincount(np.minimum(visits, 3), minlength=4)
        print(f"| {log} | scans at visit 0 / 1 / 2 / 3+ | {len(data)} scans | | "
              + " / ".join(map(str, counts)) + " |")
    if args.variants:
        variants(folder, args.radius)
    if args.figure:
        figure(folder, args.figure)


def variants(folder: Path, radius: float) -> None:
    print("\n| log | sectors | reduce | threshold (m) | hsom AUC | hsom AUC, 2nd half | nearest-memory AUC |")
    print("| --- | ---: | --- | ---: | ---: | ---: | ---: |")
    for log in LOGS:
        poses = read_recording(folder / f"{log}-corrected.log.gz").poses
        visits = visit_counts(poses, radius)
        for sectors, reduce, threshold in [(16, "min", 4.0), (8, "min", 4.0), (32, "min", 4.0),
                                           (64, "min", 4.0), (16, "mean", 4.0), (16, "median", 4.0),
                                           (16, 10, 4.0), (16, "min", 2.0), (16, "min", 8.0),
                                           (16, "min", 16.0)]:
            clip = threshold if reduce != "min" else None
            X = read_recording(folder / f"{log}-corrected.log.gz", Reading(sectors=sectors, reduce=reduce, threshold=threshold, clip=clip)).X
            h, m = scores(stream("hsom", X), visits), scores(stream("nearest-memory", X), visits)
            print(f"| {log} | {sectors} | {reduce} | {threshold:g} | {h['auc']:.3f} | {h['auc_late']:.3f} "
                  f"| {m['auc']:.3f} |")


def figure(folder: Path, out: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from novelty.io.recording.plotting import plot_path

    data = read_recording(folder / "intel-corrected.log.gz")
    visits = visit_counts(data.poses, 1.0)
    nov = stream("hsom", data.X)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2), gridspec_kw={"width_ratios": [1.25, 1]})
    plot_path(left, data.poses[:, 0], data.poses[:, 1], nov, size=7)
    left.set_title("hsom's novelty on the intel robot's path", fontsize=9)
    first = visits == 0
    right.plot(np.flatnonzero(first), nov[first], ".", ms=3, color="#d62728", label="first visit")
    right.plot(np.flatnonzero(~first), nov[~first], ".", ms=3, color="#1f77b4", label="revisit")
    right.set(xlabel="scan", ylabel="novelty", title="first visits and revisits, scan by scan")
    right.title.set_fontsize(9)
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    main()
