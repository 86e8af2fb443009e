"""Novelty along the route (matplotlib, optional): one panel, or a figure of one panel a detector.

Every mark has a legend entry: the novelty, the novel scans (shaded), the
alarm threshold (dashed; a step where it changes, none where it is not known),
the resting novelty (dotted), the stretches of scans on which an alarm was
raised (a band along the top of the axes, above the novelty) and the start of
each run (vertical lines), each drawn where the data has it. The legend goes
below the panels, where it covers nothing. The x axis is the distance along
the route when the data gives one for a single run, else the scan's index.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .figures import pyplot

__all__ = ["run_starts", "plot_route", "shade_alarms", "route_figure", "route_legend"]

#: what each mark of a route is called in its legend
NOVELTY, NOVEL, THRESHOLD, RESTING, ALARM, RUN_START = (
    "novelty", "novel scans", "alarm threshold", "resting novelty", "alarm raised", "run start")
#: the band of the alarms, in axes height: the novelty is drawn below it
_BAND = (0.93, 1.0)


def run_starts(run=None, distance=None) -> np.ndarray:
    """The scans that begin a run, the first scan aside: where the run changes, else where the
    distance along the route starts again.

    >>> run_starts(run=[0, 0, 1, 1, 2]).tolist(), run_starts(distance=[0.1, 0.2, 0.1, 0.2]).tolist()
    ([2, 4], [2])
    """
    if run is not None:
        return np.flatnonzero(np.diff(np.asarray(run)) != 0) + 1
    if distance is not None:
        return np.flatnonzero(np.diff(np.asarray(distance, dtype=float)) < 0) + 1
    return np.empty(0, dtype=np.intp)


def plot_route(ax, novelty, y=None, distance=None, threshold=None, label=NOVELTY, resting=None, run=None,
               alarm=None) -> str:
    """Novelty along the route on ``ax``, with whatever marks the data has; returns the x axis' name.

    ``y``: 1 for a novel scan (shaded); ``threshold``: a level, or one a
    scan (NaN where none is known), dashed; ``resting``: a level, dotted;
    ``run``: each scan's run, or runs found where ``distance`` starts again
    (a vertical line at each start, the x axis then the scan's index);
    ``alarm``: true where an alarm was raised (:func:`shade_alarms`).
    """
    novelty = np.asarray(novelty, dtype=float)
    starts = run_starts(run, distance)
    if distance is None or starts.size:
        x, along = np.arange(novelty.size), "scan"
    else:
        x, along = np.asarray(distance, dtype=float), "distance along the route (m)"
    top = max(float(np.nanmax(novelty)) if novelty.size else 0.0, 1e-9) * 1.05
    if y is not None and np.any(y):
        ax.fill_between(x, 0, top, where=np.asarray(y).astype(bool), color="tab:red", alpha=0.12,
                        step="mid", linewidth=0, label=NOVEL)
    ax.plot(x, novelty, linewidth=1.0, color="tab:blue", label=label)
    if threshold is not None:
        level = np.broadcast_to(np.asarray(threshold, dtype=float), novelty.shape)
        if np.isfinite(level).any():
            ax.plot(x, np.where(np.isfinite(level), level, np.nan), drawstyle="steps-mid", color="k",
                    linestyle="--", linewidth=0.8, label=THRESHOLD)
    if resting:
        ax.axhline(resting, color="0.5", linestyle=":", linewidth=0.8, label=RESTING)
    if alarm is not None:
        shade_alarms(ax, x, alarm)
    ax.set_ylim(top=top / _BAND[0])
    for i, start in enumerate(starts):
        ax.axvline(x[start], color="0.55", linewidth=0.8, label=RUN_START if i == 0 else None)
    return along


def shade_alarms(ax, x, alarm) -> None:
    """The scans on which an alarm was raised, as spans: a band along the top of ``ax`` over each stretch
    (half a scan either side of each scan, so that a lone alarm shows too); NaN (not known) is no alarm."""
    raised = np.nan_to_num(np.asarray(alarm, dtype=float), nan=0.0) == 1
    if not raised.any():
        return
    x = np.asarray(x, dtype=float)
    step = np.diff(x) if x.size > 1 else np.ones(1)
    edges = np.r_[x[0] - step[0] / 2, (x[:-1] + x[1:]) / 2, x[-1] + step[-1] / 2]
    change = np.diff(np.r_[0, raised.astype(np.int8), 0])
    first, end = np.flatnonzero(change == 1), np.flatnonzero(change == -1)   # each stretch: [first, end)
    ax.broken_barh(list(zip(edges[first], edges[end] - edges[first])), (_BAND[0], _BAND[1] - _BAND[0]),
                   transform=ax.get_xaxis_transform(), color="darkred", alpha=0.75, linewidth=0, label=ALARM)


def route_legend(fig, axes) -> None:
    """One legend for the figure, below its panels: every mark any panel drew, once."""
    entries: dict[str, object] = {}
    for ax in axes:
        for handle, name in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(name, handle)
    if entries:
        fig.legend(list(entries.values()), list(entries), loc="outside lower center", fontsize=7,
                   ncols=min(len(entries), 4), frameon=False)


def route_figure(title: str, panels: Sequence[tuple[str, dict]]):
    """One panel a detector (``(name, arrays)``: the cell's ``novelty``, ``y``, ``distance``,
    ``threshold``, ``resting``, as the bench stores them), the scans above the threshold as alarms, one
    legend below, ``title`` over all."""
    plt = pyplot()
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 1.7 * len(panels) + 1.0), squeeze=False,
                             sharex=True, layout="constrained")
    along = "scan"
    for ax, (name, a) in zip(axes[:, 0], panels):
        distance = np.asarray(a["distance"], dtype=float)
        if np.array_equal(distance, np.arange(distance.size)):  # no distance was recorded: the index
            distance = None
        threshold = float(a["threshold"])
        along = plot_route(ax, a["novelty"], a["y"], distance, threshold, resting=float(a["resting"]),
                           run=a.get("run"), alarm=np.asarray(a["novelty"], dtype=float) > threshold)
        ax.set_ylabel("novelty", fontsize=8)
        ax.set_title(name, fontsize=9, loc="left")
    axes[-1, 0].set_xlabel(along)
    fig.suptitle(title, fontsize=10)
    route_legend(fig, axes[:, 0])
    return fig
