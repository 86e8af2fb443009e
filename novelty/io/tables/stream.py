"""Scans from CSV lines as they arrive (standard input, a pipe): a header line or none, then one scan a line.

``novelty run --data -`` scores each line as it comes (``rostopic echo -p
/sonar | novelty run hsom --data - ...``). The columns are chosen and the
values checked as for a file (:mod:`novelty.io.tables.scan_file`), line by
line; nothing is read ahead of the line scored.
"""

from __future__ import annotations

import csv

import numpy as np

from .columns import plan_columns
from .scan_file import sensors_to_scans
from .table import bounded_lines, csv_rows, header_of

__all__ = ["StreamReader"]


class StreamReader:
    """Scans from CSV lines as they arrive (``lines``, a text stream): a header line (or none), then one scan a line.

    Yields ``(scan, extras)``: the sensor values (chosen and preprocessed as
    for a file) and the carried values of that line (``y``, ``distance``,
    ``run``, ``time`` in seconds). Nothing is read ahead of the line scored.
    A line that cannot be read raises a ``ValueError`` naming ``source``,
    the line and the column.

    Examples
    --------
    >>> import io
    >>> lines = io.StringIO("a,b,time\\n1,2,0.5\\n3,4,1.0\\n")
    >>> [(x.tolist(), extras) for x, extras in StreamReader(lines)]
    [([1.0, 2.0], {'time': 0.5}), ([3.0, 4.0], {'time': 1.0})]
    """

    def __init__(self, lines, columns=None, label=None, time=None, preprocess=None, threshold=None,
                 source: str = "standard input"):
        self.lines, self.source = lines, source
        self.options = dict(columns=columns, label=label, time=time)
        self.preprocess, self.threshold = preprocess, threshold

    def __iter__(self):
        rows = csv_rows(csv.reader(bounded_lines(self.lines, self.source)), self.source)
        layout = None
        for number, row in enumerate(rows, start=1):
            if not row or not any(c.strip() for c in row):
                continue
            if layout is None:
                header = header_of(row)
                layout = plan_columns(header or [f"s{i}" for i in range(len(row))], **self.options)
                if header:
                    continue
            if len(row) != len(layout.names):
                raise ValueError(f"{self.source}, line {number}: {len(row)} values, expected {len(layout.names)}.")
            where = f"{self.source}, line {number}"
            raw = np.array([[self._number(layout, j, row[j], where) for j in layout.sensors]])
            x = sensors_to_scans(raw, self.preprocess, self.threshold,
                                 lambda i, k, where=where, layout=layout:
                                 f"{where}, {layout.column(layout.sensors[k])}")[0]
            yield x, self._extras(layout, row, where)

    @staticmethod
    def _number(layout, j: int, cell: str, where: str) -> float:
        try:
            return float(cell)
        except ValueError:
            raise layout.not_a_number(j, cell, where) from None

    @classmethod
    def _extras(cls, layout, row, where: str) -> dict:
        extras = {}
        for name in ("label", "distance", "run", "time"):
            j = getattr(layout, name)
            if j is None:
                continue
            value = cls._number(layout, j, row[j], where)
            if not np.isfinite(value):
                raise ValueError(f"{where}, {layout.column(j)}: expected a finite number, got {value}.")
            if name == "label":
                extras["y"] = int(value != 0)
            elif name == "run":
                extras["run"] = int(value)
            else:
                extras[name] = value * (layout.time_scale if name == "time" else 1.0)
        return extras
