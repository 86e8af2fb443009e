"""A robot recording read whole: its options, its sweeps, rings and dataset, what the reading found.

- :mod:`~novelty.io.recording.reading`: :class:`Reading`, how a recording
  is read, one frozen set of options checked once;
- :mod:`~novelty.io.recording.readers`: :func:`read_sweeps`,
  :func:`read_rings` and :func:`read_recording` for a CARMEN log or a bag,
  by its name;
- :mod:`~novelty.io.recording.bag_sweeps` and
  :mod:`~novelty.io.recording.carmen_sweeps`: each format's messages as
  sweeps, through the layers below (:mod:`novelty.io.frames`,
  :mod:`novelty.io.scans`);
- :mod:`~novelty.io.recording.plotting`: novelty drawn along the robot's path.
"""

from .carmen_sweeps import CARMEN_LASERS, CARMEN_SUFFIXES
from .readers import Ring, is_recording, read_recording, read_rings, read_sweeps
from .reading import Reading

__all__ = ["Reading", "Ring", "read_sweeps", "read_rings", "read_recording", "is_recording", "CARMEN_SUFFIXES",
           "CARMEN_LASERS"]
