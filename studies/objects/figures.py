"""The figure of docs/guide/objects.md: a Radish log with its virtual objects, one scan, novelty on the path.

    NOVELTY_DATA_DIR=/data python studies/objects/figures.py --log intel --seed 0 --detector hsom-mismatch

writes ``docs/objects-<log>.png``: (a) the building as the laser saw it, the robot's path, the objects
drawn by the exploration task's seed and the scans that see each (first passes ringed); (b) one scan
that sees an object, the recorded beams and the ones the object shortened; (c) the detector's novelty
along the path, every scan scored before it is learned (the exploration protocol).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import novelty  # noqa: E402
from novelty.tasks.objects import cast_all, world_beams  # noqa: E402
from novelty.tasks.objects.placement import object_from_fields  # noqa: E402
from novelty.tasks.radish import radish_objects_exploration  # noqa: E402
from novelty.tasks.objects.object_tasks import LABEL_DEFAULTS, read_drive  # noqa: E402
from novelty.io.recording.plotting import plot_path  # noqa: E402
from novelty.tasks.radish import radish_log  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def _ends(sweep, ranges):
    origins, angles = world_beams(sweep)
    ok = np.isfinite(ranges) & (ranges < 20)
    return origins[ok] + ranges[ok, None] * np.c_[np.cos(angles[ok]), np.sin(angles[ok])]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--log", default="intel")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--detector", default="hsom-mismatch")
    args = parser.parse_args(argv)
    task = radish_objects_exploration(args.log, seed=args.seed)
    objects = [object_from_fields(dict(o)) for o in task.metadata["objects"]]
    sweeps = read_drive(radish_log(args.log))
    cast = cast_all(sweeps, objects, margin=LABEL_DEFAULTS["margin"], within=task.metadata["threshold_m"])
    which, exposure, poses = task.columns["object"], task.columns["exposure"], task.poses
    fig, axes = plt.subplots(1, 3, figsize=(18, 6.2))

    ax = axes[0]
    walls = np.concatenate([_ends(s, s.ranges) for s in sweeps[::3]])
    ax.plot(walls[:, 0], walls[:, 1], ",", color="0.55")
    ax.plot(poses[:, 0], poses[:, 1], "-", color="0.8", lw=0.7)
    for k, obj in enumerate(objects):
        colour = f"C{k}"
        outline = obj.outline()
        ax.fill(outline[:, 0], outline[:, 1], color=colour, zorder=4)
        mine = which == obj.name
        ax.plot(poses[mine, 0], poses[mine, 1], ".", color=colour, ms=5, zorder=3, label=f"{obj.name} seen")
        first = mine & (exposure == 0)
        ax.plot(poses[first, 0], poses[first, 1], "o", mfc="none", color=colour, ms=9, zorder=3)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set(title=f"{args.log}, seed {args.seed}: objects and the scans that see them (first pass ringed)",
           xlabel="x (m)", ylabel="y (m)")
    ax.legend(loc="best", fontsize=8)

    ax = axes[1]
    seen = np.flatnonzero(which != "")
    i = int(seen[np.argmax(cast.shortened[seen].max(axis=1))])
    recorded, new = cast.recorded[i].ranges, cast.sweeps[i].ranges
    shortened = np.isfinite(new) & (new < np.where(np.isnan(recorded), np.inf, recorded) - LABEL_DEFAULTS["margin"])
    ends = _ends(cast.recorded[i], np.where(shortened, np.nan, recorded))
    ax.plot(ends[:, 0], ends[:, 1], ".", color="0.3", ms=3, label="recorded")
    moved = _ends(cast.sweeps[i], np.where(shortened, new, np.nan))
    ax.plot(moved[:, 0], moved[:, 1], ".", color="C3", ms=4, label=f"shortened by an object ({shortened.sum()} beams)")
    for k, obj in enumerate(objects):
        outline = obj.outline()
        ax.plot(outline[:, 0], outline[:, 1], color=f"C{k}")
    x, y, yaw = poses[i]
    ax.plot([x], [y], marker=(3, 0, np.degrees(yaw) - 90), color="C0", ms=12, label="robot")
    ax.set(xlim=(x - 6, x + 6), ylim=(y - 6, y + 6), title=f"scan {i} (t = {task.columns['time'][i]:.0f} s)",
           xlabel="x (m)", ylabel="y (m)")
    ax.set_aspect("equal")
    ax.legend(loc="lower left", fontsize=8)

    ax = axes[2]
    det = novelty.make(args.detector, random_state=args.seed)
    scores = np.asarray(det.stream(task.X))
    low, high = np.percentile(scores, [2, 98])
    plot_path(ax, poses[:, 0], poses[:, 1], scores, vmin=float(low), vmax=float(high))
    for k, obj in enumerate(objects):
        outline = obj.outline()
        ax.plot(outline[:, 0], outline[:, 1], color=f"C{k}", lw=2)
    ax.set_title(f"{args.detector}: novelty along the path, each scan scored before it is learned")
    fig.tight_layout()
    out = ROOT / "docs" / f"objects-{args.log}.png"
    fig.savefig(out, dpi=72)
    print(f"wrote {out.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
