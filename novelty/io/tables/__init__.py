"""Tables of scans: every CSV, NPZ and MAT reader of the package, and the lines of a live CSV feed.

- :mod:`~novelty.io.tables.table`: a file read into named columns, bounded
  by limits the library sets (:func:`read_table`), and CSV lines read with
  the same bounds;
- :mod:`~novelty.io.tables.columns`: which column is what (sensors,
  label, time, route), by name, pattern or index (:func:`plan_columns`);
- :mod:`~novelty.io.tables.scan_file`: a file's scans as a
  :class:`~novelty.data.Dataset`, every cell checked (:func:`read_scans`);
- :mod:`~novelty.io.tables.stream`: scans from CSV lines as they arrive
  (:class:`StreamReader`, ``novelty run --data -``);
- :mod:`~novelty.io.tables.labels`: novelty labels, 0 normal and 1 novel,
  and nothing else;
- :mod:`~novelty.io.tables.smoothing`: the paper's smoothing of scans over travel;
- :mod:`~novelty.io.tables.data_files`: the user's copies of public data
  files, found (nothing is fetched) and read row by row.
"""

from .columns import Layout, plan_columns
from .scan_file import read_scans
from .stream import StreamReader
from .table import Table, read_table

__all__ = ["Table", "read_table", "Layout", "plan_columns", "read_scans", "StreamReader"]
