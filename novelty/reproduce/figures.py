"""The paper's figures 4 and 5: the output neuron along the route, trial by trial, the map's features shaded.

Shares its name with ``novelty/bench/reports/figures.py``: the paper's experiments and a benchmark's
report each draw their own figures.
"""

from __future__ import annotations

from pathlib import Path

from .trial import Trial

__all__ = ["plot_experiment1", "plot_experiments2_3", "write_figures"]

#: How each kind of map feature is marked on the distance axis: colour, short label.
_MARKS = {"door": ("#a0522d", "door"), "opening": ("#d62728", "open door"), "crack": ("#222222", "crack"),
          "board": ("#e0a526", "board"), "recess": ("#7f7f7f", "recess"), "object": ("#9467bd", "object")}
_ROUTE = (0.0, 10.0)


def pyplot():
    try:
        # optional dependency, imported only to draw
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("The figures need matplotlib: pip install matplotlib") from exc
    return plt


def _visible(features: list, kinds=None) -> list:
    """Features along the route that the sonar can hear (boards above the sonars are left out)."""
    out = []
    for f in features:
        if not (_ROUTE[0] - 0.5 <= f["position"] <= _ROUTE[1] + 0.5):
            continue
        if f["kind"] == "board" and "above the sonars" in f.get("description", ""):
            continue
        if f["id"].endswith("-frame"):
            continue  # the frame of an opened door: drawn with the opening
        out.append(f)
    return out


def _mark_features(ax, features: list, label: bool) -> None:
    """Shade each feature's extent on the distance axis; right-hand features solid, left hatched."""
    for f in _visible(features):
        colour, name = _MARKS.get(f["kind"], ("#7f7f7f", f["kind"]))
        half = max(float(f.get("width") or 0.0), 0.08) / 2
        lo, hi = f["position"] - half, f["position"] + half
        right = f.get("side") == "right"
        ax.axvspan(lo, hi, ymin=0, ymax=1, color=colour, alpha=0.10 if right else 0.05, lw=0)
        ax.axvspan(lo, hi, ymin=0, ymax=0.06, facecolor=colour if right else "none", edgecolor=colour,
                   hatch=None if right else "////", lw=0.6, alpha=0.9)
        if label:
            side = "R" if right else "L"
            ax.text(f["position"], 1.04, f"{name} {side}", transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=6.5, color=colour, rotation=0)


def _panel(ax, trial: Trial, top: bool, bottom: bool, ymax: float) -> None:
    _mark_features(ax, trial.features, label=top)
    ax.plot(trial.distance, trial.novelty, color="#1f3b73", lw=1.1, drawstyle="steps-mid")
    ax.axhline(trial.resting, color="0.35", ls="--", lw=0.8)
    ax.set_xlim(*_ROUTE)
    ax.set_ylim(0, 1.3 * ymax)  # headroom above 1.0 for the trial's label
    ax.set_yticks([0, ymax / 2, ymax])
    ax.tick_params(labelsize=7, length=2)
    ax.text(0.005, 0.97, trial.label, transform=ax.transAxes, ha="left", va="top", fontsize=8,
            fontweight="bold")
    ax.text(0.995, 0.97, f"integrated {trial.integrated:.2f}   max {trial.maximum:.2f}",
            transform=ax.transAxes, ha="right", va="top", fontsize=7)
    if not bottom:
        ax.tick_params(labelbottom=False)


def _columns(fig_title: str, columns: list[tuple[str, list[Trial]]], path, seed_note: str = ""):
    plt = pyplot()
    rows = max(len(trials) for _, trials in columns)
    # inches: titles and feature names; axis label; each trial (smaller when A needed many pairs)
    top, bottom, panel = 0.85, 0.6, (1.0 if rows <= 8 else 0.6)
    height = top + bottom + panel * rows
    fig, axes = plt.subplots(rows, len(columns), figsize=(5.4 * len(columns), height), squeeze=False)
    fig.subplots_adjust(left=0.055, right=0.99, top=1 - top / height, bottom=bottom / height,
                        hspace=0.22, wspace=0.1)
    for c, (title, trials) in enumerate(columns):
        for r in range(rows):
            ax = axes[r, c]
            if r >= len(trials):
                ax.set_visible(False)
                continue
            _panel(ax, trials[r], top=(r == 0), bottom=(r == len(trials) - 1), ymax=1.0)
            if r == len(trials) - 1:
                ax.set_xlabel("distance along the route (m)", fontsize=8, labelpad=1)
            if c == 0:
                ax.set_ylabel("novelty", fontsize=7)
        axes[0, c].set_title(title, fontsize=9, pad=13)
    fig.suptitle(fig_title + seed_note, fontsize=10, y=1 - 0.08 / height, va="top")
    fig.text(0.5, 0.04 / height, "Shaded: the map's features (solid foot: right-hand wall, followed; "
             "hatched: left). Dashed: resting activity 0.0476.", ha="center", va="bottom", fontsize=7,
             color="0.3")
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)


def _of(trials: list[Trial], experiment: str) -> list[Trial]:
    return [t for t in trials if t.experiment == experiment]


def plot_experiment1(trials: list[Trial], path, note: str = "") -> Path:
    """The paper's figure 4: A's trials on the left, A*'s on the right."""
    return _columns("Experiment 1: output of the output neuron along the route",
                    [("A: learning (L) and non-learning (NL) runs", _of(trials, "A")),
                     ("A*: the door on the right at 3 m opened", _of(trials, "A*"))], path, note)


def plot_experiments2_3(trials: list[Trial], path, note: str = "") -> Path:
    """The paper's figure 5: B and its control on the left, C and its control on the right."""
    return _columns("Experiments 2 and 3: from the model learned in A; controls trained in the open area",
                    [("B: like A; door G (right, 3.6 m) inset deeper", _of(trials, "B")),
                     ("C: wider, brick and glass, deep doorway, boards", _of(trials, "C"))], path, note)


def write_figures(trials: list[Trial], folder, note: str = "") -> list[Path]:
    """Write ``figure4-experiment1.png`` and ``figure5-experiments2-3.png`` to ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    return [plot_experiment1(trials, folder / "figure4-experiment1.png", note),
            plot_experiments2_3(trials, folder / "figure5-experiments2-3.png", note)]
