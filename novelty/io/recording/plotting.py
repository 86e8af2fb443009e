"""Novelty on the robot's path: the trajectory coloured by novelty (matplotlib, an optional extra, imported here only).

The paper's figures 4 and 5 draw novelty along a corridor; on a real
recording the route is the robot's path in the building, so the novelty
of each scan is drawn where the robot was.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_path"]


def plot_path(ax, x, y, novelty, *, cmap: str = "viridis", size: float = 8.0, colorbar: bool = True,
              vmin: float = 0.0, vmax: float = 1.0):
    """Draw the path (x, y) in metres, each scan a dot coloured by its novelty; the start marked (and
    named in the axes' legend).

    Parameters
    ----------
    ax : matplotlib Axes
    x, y, novelty : array-like of shape (n_scans,)
    cmap : str, default="viridis"
    size : float, default=8.0
        Dot size (points squared).
    colorbar : bool, default=True
    vmin, vmax : float, default=0.0, 1.0
        The novelty range of the colours.

    Returns
    -------
    The scatter's collection (for a shared colour bar).
    """
    x, y, novelty = (np.asarray(v, dtype=np.float64) for v in (x, y, novelty))
    if not (x.shape == y.shape == novelty.shape and x.ndim == 1):
        raise ValueError(f"x, y and novelty must be 1-D of one length; got {x.shape}, {y.shape}, "
                         f"{novelty.shape}.")
    ax.plot(x, y, color="0.85", lw=0.8, zorder=1)
    dots = ax.scatter(x, y, c=novelty, s=size, cmap=cmap, vmin=vmin, vmax=vmax, zorder=2, linewidths=0)
    ax.plot(x[:1], y[:1], marker="*", color="#d62728", ms=10, zorder=3, linestyle="none", label="start")
    ax.legend(fontsize=7, loc="best")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set(xlabel="x (m)", ylabel="y (m)")
    if colorbar:
        ax.figure.colorbar(dots, ax=ax, label="novelty", shrink=0.8)
    return dots
