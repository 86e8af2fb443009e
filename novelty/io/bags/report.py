"""What reading a recording did, in a few lines for the console: scans assembled, frames and mounts used.

The readers fill a :class:`ReadReport` as they go (``report=`` of
:func:`novelty.io.read_sweeps` and :func:`novelty.io.read_rings`);
``novelty run`` prints its :meth:`~ReadReport.lines` on standard error.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["ReadReport"]


@dataclass
class ReadReport:
    """What a reading found and chose.

    Attributes
    ----------
    assembly : dict
        Per scan topic: ``(messages, scans, incomplete, fragments a revolution)``.
    mounts : dict
        Per sensor (topic): how its beams were placed in the base frame.
    base_frame : str
        The robot's frame used ("" when the recording names none).
    base_reason : str
        Why that frame (REP 105's default, a fallback, the user's).
    poses : str
        Where the poses came from, or why there are none.
    merged : tuple of int or None
        With several sensors: sweeps merged, sweeps left without partners.
    notes : list of str
        Anything else the user should know.
    skipped : int
        Transforms left out of the tf tree, as tf2 leaves them out (one frame
        named twice, no rotation, a loop, a chain beyond the bounds);
        ``first_skipped`` says where the first is and why.
    """

    assembly: dict = field(default_factory=dict)
    mounts: dict = field(default_factory=dict)
    base_frame: str = ""
    base_reason: str = ""
    poses: str = ""
    merged: tuple | None = None
    notes: list = field(default_factory=list)
    skipped: int = 0
    first_skipped: str = ""

    def skip(self, where, why: str) -> None:
        """Count a transform left out of the tree (``where`` it is in the recording, ``why``)."""
        self.skipped += 1
        if self.skipped == 1:
            self.first_skipped = f"{where}: {why}"

    @property
    def has_poses(self) -> bool:
        """Whether the reading looks poses up (some rows may still have none: before the first)."""
        return self.poses.startswith("from")

    def lines(self) -> list[str]:
        out = []
        for topic, (messages, scans, incomplete, per) in self.assembly.items():
            if per and per > 1:
                out.append(f"{topic}: {scans} scans assembled from {messages} messages ({per} a revolution"
                           + (f"; {incomplete} incomplete revolution{'s' * (incomplete != 1)} left out)"
                              if incomplete else ")"))
        if self.base_frame:
            out.append(f"base frame {self.base_frame} ({self.base_reason})")
        out += [f"{topic}: {how}" for topic, how in self.mounts.items()]
        if self.poses:
            out.append(f"poses {self.poses}")
        if self.merged is not None:
            out.append(f"{self.merged[0]} sweeps merged from {len(self.mounts)} sensors ({self.merged[1]} left "
                       "without partners within the tolerance)")
        if self.skipped:
            out.append(f"{self.skipped} transform{'s' * (self.skipped != 1)} skipped, as tf2 skips them (the first: "
                       f"{self.first_skipped})")
        return out + list(self.notes)
