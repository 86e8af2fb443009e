"""What every plot of the harness shares: matplotlib on demand, file names, grids, saving.

matplotlib is optional: :func:`matplotlib_missing` says in one line what to
install when it is absent, and :func:`pyplot` imports it (with the
non-interactive Agg backend) only when a plot is drawn.

Shares its name with ``novelty/reproduce/figures.py``: the paper's experiments and a benchmark's
report each draw their own figures.
"""

from __future__ import annotations

import hashlib
import math
import re
import textwrap
from pathlib import Path
from typing import Sequence

__all__ = ["matplotlib_missing", "pyplot", "slug", "grid", "save", "seeds_text", "wrapped", "DPI", "MAX_SLUG"]

#: resolution of every saved figure
DPI = 110


def matplotlib_missing() -> str | None:
    """``None`` if matplotlib is importable, else the line to tell the user."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return "Plots skipped: matplotlib is not installed (pip install 'novelty-habituation[plot]')."
    return None


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (optional dependency, imported only to draw)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


#: the longest part of a file name a label becomes (file systems allow 255 bytes a name)
MAX_SLUG = 80


def slug(text: str) -> str:
    """``text`` as a safe part of a file name, one name a text.

    A text of letters, digits, ``_.-`` only and at most :data:`MAX_SLUG`
    characters is its own name. Any other is cleaned (each run of other
    characters a ``-``), cut to fit, and followed by 8 hex digits of the
    text's SHA-256: so two labels never write one file (``lab a`` and
    ``lab/a`` would both clean to ``lab-a``), and a label of 300 characters
    makes a name a file system takes.

    >>> slug("lab-a_2.csv"), slug("lab a/b.csv")
    ('lab-a_2.csv', 'lab-a-b.csv-addaa40a')
    >>> len(slug("x" * 300)) <= MAX_SLUG
    True
    """
    if re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.-]*", text) and len(text) <= MAX_SLUG:
        return text
    cleaned = re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-.") or "task"
    digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:8]
    return f"{cleaned[:MAX_SLUG - 9]}-{digest}"


def grid(n: int) -> tuple[int, int]:
    """Rows and columns (at most 3) for ``n`` panels."""
    cols = min(n, 3)
    return math.ceil(n / cols), cols


def save(fig, path: Path, tight: bool = True) -> Path:
    """Lay out (unless ``tight`` is false: a figure placed by hand), write and close ``fig``; return ``path``."""
    plt = pyplot()
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def seeds_text(seeds: Sequence[int]) -> str:
    """``"seed 3"`` or ``"seeds 0, 1, 2"``.

    >>> seeds_text([2, 0, 1]), seeds_text([3])
    ('seeds 0, 1, 2', 'seed 3')
    """
    seeds = sorted(set(int(s) for s in seeds))
    return ("seed " if len(seeds) == 1 else "seeds ") + ", ".join(map(str, seeds))


def wrapped(text: str, fig, fontsize: float = 10) -> str:
    """``text`` in lines that fit across ``fig`` at ``fontsize`` (a title over a narrow figure)."""
    width_points = fig.get_figwidth() * 72
    return "\n".join(textwrap.wrap(text, max(20, int(width_points / (0.55 * fontsize)))))
