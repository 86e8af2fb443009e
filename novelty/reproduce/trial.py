"""One trial of the protocol, and the paper's criterion that a run shows only the resting activity."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Trial", "is_resting", "RESTING_INTEGRATED", "RESTING_MAXIMUM"]

#: A non-learning run "shows only the resting activity" (:func:`is_resting`) when its
#: integrated output is at most this and its maximum at most :data:`RESTING_MAXIMUM`.
#: Both lie between the paper's settled run (A trial 6: 0.30, 0.12) and its last
#: unsettled one (A trial 4: 1.07, 0.42).
RESTING_INTEGRATED = 0.5
RESTING_MAXIMUM = 0.2


@dataclass
class Trial:
    """One run of the protocol and what the output neuron did along it.

    ``paired`` is set for the non-learning trials of A*: the novelty the same
    model gives to the traversal of A drawn with the same random numbers
    (the same start, speed and jitter; the door shut), so that ``novelty -
    paired`` is what opening the door changed.
    """

    experiment: str
    trial: str
    mode: str  # "L" or "NL"
    novelty: np.ndarray
    distance: np.ndarray
    resting: float
    run: int
    features: list = field(default_factory=list)
    paired: np.ndarray | None = None

    @property
    def integrated(self) -> float:
        """Output summed over the run, the resting activity subtracted each step."""
        return float(np.sum(self.novelty - self.resting))

    @property
    def maximum(self) -> float:
        return float(np.max(self.novelty))

    @property
    def label(self) -> str:
        """The trial as Table 1 names it: ``"3 (L)"`` or ``"Control"``."""
        return self.trial if self.trial == "Control" else f"{self.trial} ({self.mode})"

    def near(self, position: float, half_width: float = 1.0) -> np.ndarray:
        """Mask of the scans taken within ``half_width`` metres of ``position`` along the route."""
        return np.abs(self.distance - position) <= half_width


def is_resting(trial: Trial, integrated: float = RESTING_INTEGRATED,
               maximum: float = RESTING_MAXIMUM) -> bool:
    """Whether a run shows only the resting activity of the output neuron.

    The paper's criterion for having learned an environment (section 3.2):
    "the output of the novelty filter was only the resting activity of the
    output neuron throughout the run". In numbers: at most ``integrated``
    above the resting activity over the run and no scan above ``maximum``.

    >>> flat = Trial("A", "6", "NL", np.full(100, 0.0476), np.arange(1, 101) / 10, 0.0476, run=5)
    >>> is_resting(flat), round(flat.integrated, 6)
    (True, 0.0)
    >>> flat.novelty[30] = 0.42  # one scan still novel
    >>> is_resting(flat)
    False
    """
    return trial.integrated <= integrated and trial.maximum <= maximum
