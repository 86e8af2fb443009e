"""Finding and reading the user's copies of public data files (nothing is fetched)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["DATA_DIR_ENV", "resolve_data_file", "read_rows", "is_float"]

#: Environment variable naming a folder that holds the dataset folders
#: (``wall-following-robot-navigation/``, ``sonar-mines-vs-rocks/``).
DATA_DIR_ENV = "NOVELTY_DATA_DIR"


def resolve_data_file(path, filename: str, folder: str, dataset: str) -> Path:
    """The file ``filename`` of ``dataset``, from ``path`` or ``$NOVELTY_DATA_DIR``.

    ``path`` may be the file itself, the folder holding it, or a folder
    holding ``folder/filename``. Without ``path``, ``$NOVELTY_DATA_DIR`` is
    searched the same way.
    """
    if path is None:
        root = os.environ.get(DATA_DIR_ENV)
        if not root:
            raise FileNotFoundError(
                f"Where is the {dataset} data? Pass path= (the file {filename!r} or a folder "
                f"holding it), or set the environment variable {DATA_DIR_ENV} to a folder that "
                f"contains {folder}/{filename}. Nothing is downloaded.")
        base, origin = Path(root).expanduser(), f"{DATA_DIR_ENV}={root}"
    else:
        base, origin = Path(path).expanduser(), f"path={str(path)!r}"
    if base.is_file():
        return base
    candidates = [base / filename, base / folder / filename]
    for c in candidates:
        if c.is_file():
            return c
    raise FileNotFoundError(
        f"No {dataset} file found from {origin}: looked for "
        + ", ".join(str(c) for c in candidates) + ".")


def read_rows(file: Path, n_values: int, labels, value_range=None):
    """Rows of ``n_values`` comma-separated floats then a label, validated.

    Returns ``(values, labels)``. Any malformed line raises ``ValueError``
    naming the file and the line number. Blank lines are skipped; CRLF and
    LF line endings are both accepted.
    """
    values, names = [], []
    with open(file, "r", encoding="utf-8", newline=None) as fh:
        for number, line in enumerate(fh, start=1):
            text = line.strip()
            if not text:
                continue
            fields = [f.strip() for f in text.split(",")]
            where = f"{file}, line {number}"
            if len(fields) != n_values + 1:
                raise ValueError(f"{where}: expected {n_values} numbers and a label "
                                 f"({n_values + 1} comma-separated fields), found {len(fields)}.")
            try:
                row = [float(f) for f in fields[:n_values]]
            except ValueError:
                bad = next(f for f in fields[:n_values] if not is_float(f))
                raise ValueError(f"{where}: {bad!r} is not a number.") from None
            if not all(np.isfinite(row)):
                raise ValueError(f"{where}: values must be finite.")
            if value_range is not None and not all(value_range[0] <= v <= value_range[1] for v in row):
                raise ValueError(f"{where}: values must lie in [{value_range[0]}, {value_range[1]}].")
            if fields[-1] not in labels:
                raise ValueError(f"{where}: unknown label {fields[-1]!r}; expected one of "
                                 f"{', '.join(labels)}.")
            values.append(row)
            names.append(fields[-1])
    if not values:
        raise ValueError(f"{file}: no data rows.")
    return np.asarray(values, dtype=np.float64), np.asarray(names)


def is_float(text: str) -> bool:
    """Whether ``text`` reads as a float (``nan``, ``inf`` and ``1e3`` included)."""
    try:
        float(text)
    except ValueError:
        return False
    return True
