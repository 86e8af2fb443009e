"""Alarm policies for a stream of novelty scores: when to tell someone.

A detector scores each scan; an alarm policy turns the scores, one at a
time, into raised / clear. One threshold (:class:`Threshold`, what
``predict`` does) fires on every isolated spike; a robot exploring or a
monitored machine usually wants

- :class:`KOfN`: raised while at least ``k`` of the last ``n`` scans were
  novel (the "k-out-of-n" or "m-of-n" detection rule of radar and
  statistical process control), which ignores lone spikes;
- :class:`Hysteresis`: raised once novelty exceeds ``high``, cleared only
  when it falls below ``low`` (a Schmitt trigger), which does not flicker
  when novelty hovers about one threshold.

They compose: :class:`KOfN` counts the scans on which another policy is
raised (a :class:`Threshold` by default, or a :class:`Hysteresis`).
Every policy is a small object with :meth:`~Alarm.update` (one score, the
state after it), :meth:`~Alarm.run` (a sequence, continuing the same
stream) and :meth:`~Alarm.reset`. :func:`parse_alarm` reads the short
form the command line takes (``k-of-n:3,5``, ``hysteresis:0.7,0.4``).

Higher novelty = more novel; "above" is strict, as in ``predict``: a score
equal to the threshold is not novel.

Examples
--------
>>> alarm = KOfN(2, 3, Threshold(0.5))
>>> alarm.run([0.9, 0.1, 0.9, 0.1, 0.1]).tolist()
[False, False, True, False, False]
>>> Hysteresis(high=0.7, low=0.3).run([0.5, 0.8, 0.4, 0.2]).tolist()
[False, True, True, False]

References
----------
Western Electric (1956). Statistical Quality Control Handbook. Western
Electric Co. (run rules such as "2 of 3 successive points beyond the
2-sigma limit": k of the last n).

Skolnik, M. I. (2001). Introduction to Radar Systems, 3rd ed. McGraw-Hill
(binary integration: an m-out-of-n detection rule).

Schmitt, O. H. (1938). A thermionic trigger. Journal of Scientific
Instruments, 15(1), 24-26 (the trigger with two thresholds: hysteresis).
"""

from __future__ import annotations

import math
import numbers
from abc import ABC, abstractmethod
from collections import deque
from typing import Iterable

import numpy as np

from ._markup import counted
from ._validation import Interval

__all__ = ["Alarm", "Threshold", "KOfN", "Hysteresis", "parse_alarm", "ALARM_FORMS"]

_REAL = Interval(numbers.Real, None, None)


def _check(owner: str, name: str, value, rule: Interval) -> None:
    if not rule.accepts(value):
        raise ValueError(f"The '{name}' parameter of {owner} must be {rule.describe()}. Got {value!r} instead.")


class Alarm(ABC):
    """A policy that turns a stream of novelty scores into raised / clear."""

    @abstractmethod
    def _step(self, novelty: float) -> bool:
        """Take one (checked) score; return whether the alarm is raised after it."""

    @abstractmethod
    def reset(self) -> None:
        """Forget the stream: the alarm is clear and has seen nothing."""

    @property
    @abstractmethod
    def level(self) -> float:
        """The novelty a scan must be above to count towards raising the alarm (for plots and outputs)."""

    def update(self, novelty: float) -> bool:
        """Take the novelty of the next scan; return whether the alarm is raised now."""
        if isinstance(novelty, bool) or not isinstance(novelty, numbers.Real) or math.isnan(novelty):
            raise ValueError(f"{type(self).__name__} takes novelty scores as numbers; got {novelty!r}.")
        return self._step(float(novelty))

    def run(self, novelties: Iterable[float]) -> np.ndarray:
        """:meth:`update` on each score in turn (continuing the stream); the states, as booleans."""
        return np.array([self.update(v) for v in np.asarray(novelties, dtype=np.float64).ravel().tolist()],
                        dtype=bool)


class Threshold(Alarm):
    """Raised exactly while the current score is above ``threshold`` (what ``predict`` does).

    Parameters
    ----------
    threshold : float
        Novelty above which (strictly) a scan is novel; ``inf`` raises no alarm.
    """

    def __init__(self, threshold: float):
        if threshold != math.inf:  # +inf: no score is above it (a threshold too few scans calibrated)
            _check("Threshold", "threshold", threshold, _REAL)
        self.threshold = float(threshold)

    def _step(self, novelty: float) -> bool:
        return novelty > self.threshold

    def reset(self) -> None:
        """A single threshold has no memory."""

    @property
    def level(self) -> float:
        return self.threshold

    def __repr__(self) -> str:
        return f"Threshold({self.threshold!r})"


class KOfN(Alarm):
    """Raised while at least ``k`` of the last ``n`` scans raised ``of``.

    Until ``n`` scans have been seen, the window holds those seen so far,
    so the alarm can be raised from the ``k``-th scan on.

    Parameters
    ----------
    k : int
        How many of the window's scans must be novel, in [1, n].
    n : int
        Length of the window, in scans.
    of : Alarm or float
        The per-scan policy counted; a number is taken as ``Threshold(of)``.
    """

    def __init__(self, k: int, n: int, of: Alarm | float):
        _check("KOfN", "n", n, Interval(numbers.Integral, 1, None))
        _check("KOfN", "k", k, Interval(numbers.Integral, 1, n))
        self.k, self.n = int(k), int(n)
        self.of = of if isinstance(of, Alarm) else Threshold(of)
        self._window: deque[bool] = deque(maxlen=self.n)
        self._count = 0

    def _step(self, novelty: float) -> bool:
        if len(self._window) == self.n:
            self._count -= self._window[0]
        hit = self.of._step(novelty)
        self._window.append(hit)
        self._count += hit
        return self._count >= self.k

    def reset(self) -> None:
        """Empty the window and reset the counted policy."""
        self._window.clear()
        self._count = 0
        self.of.reset()

    @property
    def level(self) -> float:
        return self.of.level

    def __repr__(self) -> str:
        return f"KOfN({self.k}, {self.n}, {self.of!r})"


class Hysteresis(Alarm):
    """Raised when a score exceeds ``high``; cleared only when one falls below ``low``.

    Scores between ``low`` and ``high`` (inclusive) keep the alarm as it was.

    Parameters
    ----------
    high : float
        Raise above this (strictly).
    low : float
        Clear below this (strictly); at most ``high``.
    """

    def __init__(self, high: float, low: float):
        _check("Hysteresis", "high", high, _REAL)
        _check("Hysteresis", "low", low, Interval(numbers.Real, None, high))
        self.high, self.low = float(high), float(low)
        self._raised = False

    def _step(self, novelty: float) -> bool:
        if novelty > self.high:
            self._raised = True
        elif novelty < self.low:
            self._raised = False
        return self._raised

    def reset(self) -> None:
        """Clear the alarm."""
        self._raised = False

    @property
    def level(self) -> float:
        return self.high

    def __repr__(self) -> str:
        return f"Hysteresis(high={self.high!r}, low={self.low!r})"


#: The short forms :func:`parse_alarm` reads, for help texts.
ALARM_FORMS = ("threshold[:T]", "k-of-n:K,N[,T]", "hysteresis:HIGH,LOW")


def parse_alarm(spec: str, threshold: float | None = None) -> Alarm:
    """Build an alarm policy from its short form.

    Parameters
    ----------
    spec : str
        ``"threshold"`` or ``"threshold:T"``; ``"k-of-n:K,N"`` or
        ``"k-of-n:K,N,T"`` (K of the last N scans above T);
        ``"hysteresis:HIGH,LOW"``.
    threshold : float, optional
        T where the form leaves it out (a detector's ``threshold_``).

    Examples
    --------
    >>> parse_alarm("k-of-n:3,5", threshold=0.5)
    KOfN(3, 5, Threshold(0.5))
    >>> parse_alarm("hysteresis:0.7,0.4")
    Hysteresis(high=0.7, low=0.4)
    """
    name, _, rest = str(spec).strip().partition(":")
    name = name.strip().lower()
    try:
        args = [float(a) for a in rest.split(",")] if rest.strip() else []
    except ValueError:
        raise ValueError(f"Alarm {spec!r}: the values after ':' must be numbers separated by commas.") from None
    shapes = {"threshold": (0, 1), "k-of-n": (2, 3), "hysteresis": (2, 2)}
    if name not in shapes:
        raise ValueError(f"Unknown alarm {spec!r}; expected one of {', '.join(ALARM_FORMS)}.")
    least, most = shapes[name]
    if not least <= len(args) <= most:
        form = next(f for f in ALARM_FORMS if f.startswith(name))
        raise ValueError(f"Alarm {spec!r} takes {form}; got {counted(len(args), 'value')}.")
    if name == "hysteresis":
        return Hysteresis(args[0], args[1])
    if name == "k-of-n" and not all(math.isfinite(v) and v == int(v) for v in args[:2]):
        raise ValueError(f"Alarm {spec!r}: K and N are whole numbers of scans; got {args[0]:g} and {args[1]:g}.")
    t = args[-1] if len(args) == most else threshold
    if t is None:
        raise ValueError(f"Alarm {spec!r} needs a threshold: give it in the form or from the detector.")
    if name == "threshold":
        return Threshold(t)
    return KOfN(int(args[0]), int(args[1]), Threshold(t))
