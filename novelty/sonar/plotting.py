"""Figures of the sonar world (matplotlib is an optional extra, imported here only).

- :func:`plot_map`: the map (walls coloured by material, features named), the
  route driven, and the sonar cones of one ring with their echoes;
- :func:`plot_scans`: a run's perceptions as an image, distance along the
  route across, sensors down, with the map's features marked.
"""

from __future__ import annotations

import numpy as np

from .environments import get_environment
from .ranger import PolaroidRanger
from .robot import NOMAD_200

__all__ = ["plot_map", "plot_scans", "plot_run"]

_SOURCE_COLOURS = {1: "#d62728", 2: "#9467bd", 3: "#2ca02c"}
_SOURCE_NAMES = {1: "direct echo", 2: "multipath echo", 3: "edge echo"}
_KIND_COLOURS = {"door": "#a0522d", "crack": "#444444", "board": "#e0a526", "recess": "#7f7f7f",
                 "opening": "#1f77b4", "object": "#d62728"}


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("Plotting needs matplotlib: pip install matplotlib") from exc
    return plt


def plot_map(environment, dataset=None, scan: int | None = None, ax=None, *,
             ranger: PolaroidRanger = PolaroidRanger(), robot=NOMAD_200, xlim=None, ylim=None,
             labels: bool = True):
    """Draw a map, the route and the sonar returns of one scan.

    Parameters
    ----------
    environment : str or Environment
    dataset : Dataset, optional
        A simulated run; its poses are drawn as the route driven. Without it
        the nominal route is drawn.
    scan : int, optional
        Index of the scan whose pose gets a robot and its 16 sonar cones with
        their (noiseless) first echoes: direct, multipath or from an edge.
    ax : matplotlib Axes, optional
    ranger, robot
        The sensor models used for the cones.
    xlim, ylim : tuple, optional
        Axis limits (default: around the route).
    labels : bool, default=True
        Name the features.

    Returns
    -------
    matplotlib Axes
    """
    plt = _pyplot()
    # optional dependency, imported only to draw
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Circle, Wedge

    env = get_environment(environment)
    w = env.world
    if ax is None:
        _, ax = plt.subplots(figsize=(12, 3.6))
    colours = [w.materials[m].colour for m in w.material]
    solid = [i for i, c in enumerate(colours) if c != "none"]
    ax.add_collection(LineCollection(np.stack([w.p0[solid], w.p1[solid]], axis=1),
                                     colors=[colours[i] for i in solid], linewidths=2.2))
    apertures = [i for i, c in enumerate(colours) if c == "none"]
    if apertures:
        ax.add_collection(LineCollection(np.stack([w.p0[apertures], w.p1[apertures]], axis=1),
                                         colors="#1f77b4", linewidths=1, linestyles=":"))
    if w.edges.shape[0]:
        ax.plot(w.edges[:, 0], w.edges[:, 1], ".", color="k", ms=3)
    if labels:
        for f in w.features:
            dy = -0.25 if f.side == "right" else 0.25
            ax.annotate(f.id, f.centre, xytext=(f.centre[0], f.centre[1] + dy), fontsize=7,
                        ha="center", va="center", color=_KIND_COLOURS.get(f.kind, "k"))
    if dataset is not None and dataset.poses is not None:
        ax.plot(dataset.poses[:, 0], dataset.poses[:, 1], "-", color="#2b8cbe", lw=1,
                label="route driven")
    else:
        ax.plot(env.route[:, 0], env.route[:, 1], "--", color="#2b8cbe", lw=1, label="route")
    if scan is not None:
        if dataset is None or dataset.poses is None:
            raise ValueError("Pass the dataset whose scan to draw.")
        pose = dataset.poses[scan]
        echoes = ranger.cast(w, pose[None, :], robot)
        pos, axis = robot.sonar_poses(pose[None, :])
        half = np.degrees(ranger.beam_half_angle)
        for i in range(axis.shape[1]):
            r = echoes.ranges[0, i]
            reach = r if np.isfinite(r) else 4.0
            ax.add_patch(Wedge(pos[0, i], reach, np.degrees(axis[0, i]) - half,
                               np.degrees(axis[0, i]) + half, color="#fdae6b", alpha=0.25, lw=0))
            if np.isfinite(r):
                a = np.radians(np.linspace(-half, half, 9)) + axis[0, i]
                ax.plot(pos[0, i, 0] + r * np.cos(a), pos[0, i, 1] + r * np.sin(a), "-",
                        color=_SOURCE_COLOURS[int(echoes.source[0, i])], lw=1.5)
        for s, name in _SOURCE_NAMES.items():
            ax.plot([], [], "-", color=_SOURCE_COLOURS[s], label=name)
        ax.add_patch(Circle(pose[:2], robot.radius, fill=False, color="k", lw=1))
        ax.plot([pose[0], pose[0] + robot.radius * np.cos(pose[2])],
                [pose[1], pose[1] + robot.radius * np.sin(pose[2])], "k-", lw=1)
    route = dataset.poses[:, :2] if dataset is not None and dataset.poses is not None else env.route
    ax.set_xlim(xlim or (route[:, 0].min() - 1.5, route[:, 0].max() + 1.5))
    ax.set_ylim(ylim or (min(route[:, 1].min(), 0) - 1.2, route[:, 1].max() + 2.0))
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(env.description, fontsize=8)
    ax.legend(loc="upper right", fontsize=7, ncol=4)
    return ax


def plot_scans(dataset, ax=None, *, features: bool = True, colorbar: bool = True):
    """Draw a run's scans as an image: distance along the route across, sensors down.

    Sensor rows are labelled by direction (0 = ahead, 90 = left, 180 =
    behind, 270 = right, the followed wall); the map's features are marked
    above the image at their position along the route.

    Returns
    -------
    matplotlib Axes
    """
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(12, 3.2))
    X = dataset.X
    d = dataset.distance if dataset.distance is not None else np.arange(1, len(X) + 1) * 0.1
    step = float(np.median(np.diff(d))) if len(d) > 1 else 0.1
    image = ax.imshow(X.T, aspect="auto", origin="upper", cmap="magma", vmin=0, vmax=1,
                      extent=(d[0] - step, d[-1], X.shape[1] - 0.5, -0.5), interpolation="nearest")
    angles = dataset.metadata.get("sensor_angles_deg")
    if angles is not None and len(angles) == X.shape[1]:
        ticks = [i for i, a in enumerate(angles) if round(a) % 90 == 0]
        ax.set_yticks(ticks)
        ax.set_yticklabels([f"{int(round(angles[i]))}°" for i in ticks])
    ax.set_ylabel("sensor direction")
    ax.set_xlabel("distance along the route (m)")
    if features:
        for f in dataset.metadata.get("features", []):
            if d[0] - 1 <= f["position"] <= d[-1] + 1:
                c = _KIND_COLOURS.get(f["kind"], "k")
                ax.axvline(f["position"], color=c, lw=0.8, ls="--", alpha=0.8)
                ax.text(f["position"], -0.7, f["id"], rotation=90, fontsize=7, color=c,
                        ha="center", va="bottom")
    if colorbar:
        plt.colorbar(image, ax=ax, pad=0.01, label="1 - min(r, 4 m)/4 m")
    ax.set_title(f"{dataset.name}: {len(X)} scans", fontsize=9, pad=28 if features else 6)
    return ax


def plot_run(environment, dataset, scan: int = 30, path=None):
    """Both figures stacked for one run; saved to ``path`` if given. Returns the Figure."""
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(12, 7.5), constrained_layout=True)
    plot_map(environment, dataset, scan, ax=top)
    plot_scans(dataset, ax=bottom)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
