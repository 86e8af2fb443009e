"""The familiar stretch on the command line: ``--calibrate`` and ``--false-alarm-rate``.

A stretch the robot knows is named one of three ways:

- ``A:B``: the scans of ``--data`` taken from ``A`` to ``B`` seconds after its
  first scan (a recording, or a file with a time column); ``A:`` to the end;
- ``rows:I:J``: the rows ``I`` to ``J - 1`` of ``--data`` (0-based; ``rows:I:``
  to the end);
- a file or recording of its own, read with the same options as ``--data``.

``novelty score`` scores the stretch frozen, as it scores everything;
``novelty run`` takes the novelty each scan of the stretch had as it was
streamed (scored, then learned), as the run scores. Either way the threshold
is the split-conformal one (:mod:`novelty.conformal`), for the rate given.
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass

import numpy as np

from ..alarms import parse_alarm
from ..conformal import CalibrationWarning, check_rate, conformal_p_values
from ._common import UserError

__all__ = ["Stretch", "add_calibration_options", "stretch_of", "StreamCalibration", "say_calibration",
           "p_values", "threshold_in_force"]

_FORMS = "A:B (seconds after the first scan of --data), rows:I:J (rows of --data, 0-based, J excluded), or a file"


@dataclass(frozen=True)
class Stretch:
    """A familiar stretch: rows or seconds of ``--data``, or a file of its own."""

    text: str
    rows: tuple[int, float] | None = None       # first row, row after the last (inf: to the end)
    seconds: tuple[float, float] | None = None  # from, to, after the first scan's time
    path: str | None = None

    def holds(self, index: int, elapsed: float | None) -> bool:
        """Whether scan ``index`` of ``--data``, taken ``elapsed`` seconds after the first, is in the stretch."""
        if self.rows is not None:
            return self.rows[0] <= index < self.rows[1]
        if elapsed is None:
            raise UserError(f"--calibrate {self.text} names seconds, and --data has no time column: name its "
                            "rows instead (rows:I:J).")
        return self.seconds[0] <= elapsed < self.seconds[1]

    def passed(self, index: int, elapsed: float | None) -> bool:
        """Whether scan ``index`` comes after the stretch (so every scan of it has been seen)."""
        if self.rows is not None:
            return index >= self.rows[1]
        return elapsed is not None and elapsed >= self.seconds[1]

    def describe(self, data: str) -> str:
        if self.path is not None:
            return self.path
        if self.rows is not None:
            end = "the end" if math.isinf(self.rows[1]) else f"{int(self.rows[1]) - 1}"
            return f"{data}, rows {self.rows[0]} to {end}"
        end = "the end" if math.isinf(self.seconds[1]) else f"{self.seconds[1]:g} s"
        return f"{data}, {self.seconds[0]:g} s to {end} after its first scan"


def add_calibration_options(parser, how: str) -> None:
    """``--calibrate`` and ``--false-alarm-rate``; ``how`` says how the stretch is scored."""
    group = parser.add_argument_group(
        "alarms at a stated false-alarm rate (split-conformal: the threshold is set from the novelty of a "
        f"stretch the robot knows, {how})")
    group.add_argument("--calibrate", metavar="STRETCH",
                       help=f"the familiar stretch: {_FORMS} read as --data is")
    group.add_argument("--false-alarm-rate", type=float, metavar="A",
                       help="the rate of alarms on familiar scans, in (0, 1) (default 0.01 with --calibrate)")


def stretch_of(args) -> Stretch | None:
    """The ``--calibrate`` stretch, checked with ``--false-alarm-rate``; None without it."""
    if args.calibrate is None:
        if args.false_alarm_rate is not None:
            raise UserError("--false-alarm-rate needs --calibrate: the familiar stretch its threshold is set from.")
        return None
    if args.false_alarm_rate is None:
        args.false_alarm_rate = 0.01
    try:
        check_rate(args.false_alarm_rate)
    except ValueError:
        raise UserError(f"--false-alarm-rate must be a number in (0, 1); got {args.false_alarm_rate:g}.") from None
    return parse_stretch(args.calibrate)


def parse_stretch(text: str) -> Stretch:
    """``A:B``, ``rows:I:J`` or a path (see the module docstring)."""
    head, _, rest = text.partition(":")
    if head == "rows":
        low, _, high = rest.partition(":")
        try:
            first = int(low) if low else 0
            end = float(int(high)) if high else math.inf
        except ValueError:
            raise UserError(f"--calibrate rows:I:J takes whole row numbers; got {text!r}.") from None
        if first < 0 or end <= first:
            raise UserError(f"--calibrate {text}: expected 0 <= I < J.")
        return Stretch(text, rows=(first, end))
    if ":" in text and _number(head) is not None and (rest == "" or _number(rest) is not None):
        low, high = _number(head), math.inf if rest == "" else _number(rest)
        if not 0 <= low < high:
            raise UserError(f"--calibrate {text}: expected 0 <= A < B seconds.")
        return Stretch(text, seconds=(low, high))
    return Stretch(text, path=text)


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def threshold_in_force(det, command: str) -> float | None:
    """``det.threshold_`` (None for a detector without one), its advice said as the command line says it."""
    if not hasattr(type(det), "threshold_"):
        return None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CalibrationWarning)
        threshold = det.threshold_
    for warning in caught:
        if issubclass(warning.category, CalibrationWarning):
            advice = str(warning.message).split(" For a false-alarm rate")[0]
            print(f"{command}: {advice} Give --calibrate with a stretch the robot knows (and "
                  "--false-alarm-rate) for alarms at a stated rate.", file=sys.stderr)
    return threshold


def say_calibration(det, command: str) -> None:
    """One line on standard error: the threshold set, for which rate, from what."""
    threshold = det.threshold_
    at = "infinite: no scan raises an alarm" if math.isinf(threshold) else f"{threshold:.6g}"
    print(f"{command}: threshold {at}, for a false-alarm rate of {det.false_alarm_rate_:g} on familiar scans, "
          f"from {det.calibrated_on_}.", file=sys.stderr)


def p_values(det, novelty) -> np.ndarray | None:
    """The conformal p-value of each novelty against a calibrated detector's familiar scans; None if uncalibrated."""
    if not hasattr(det, "familiar_scores_"):
        return None
    return conformal_p_values(novelty, det.familiar_scores_)


class StreamCalibration:
    """Calibrates a learning detector on a stretch of ``--data`` as the stream passes it, scan by scan.

    :meth:`row` gives each scan's ``alarm``, ``threshold`` and ``p_value``: NaN (an
    empty cell) until the stretch has passed (the threshold is not known when those
    rows are written), then the calibrated threshold's (through the ``--alarm``
    policy).
    """

    def __init__(self, det, stretch: Stretch, rate: float, source: str, policy: str | None, command: str):
        self.det, self.stretch, self.rate, self.source = det, stretch, rate, source
        self.policy, self.command = policy, command
        self.scores: list[float] = []
        self.alarm = None   # the policy, once calibrated
        self.first_time: float | None = None

    def row(self, index: int, time: float | None, novelty: float) -> dict:
        if self.first_time is None and time is not None:
            self.first_time = time
        elapsed = None if time is None else time - self.first_time
        if self.alarm is None and self.scores and self.stretch.passed(index, elapsed):
            self.finish()
        if self.alarm is None:
            if self.stretch.holds(index, elapsed):
                self.scores.append(novelty)
            return {"alarm": math.nan, "threshold": math.nan, "p_value": math.nan}
        return {"alarm": int(self.alarm.update(novelty)), "threshold": self.alarm.level,
                "p_value": float(conformal_p_values([novelty], self.det.familiar_scores_)[0])}

    def finish(self) -> None:
        """Calibrate on the scores gathered (at the stretch's end, or the data's)."""
        if self.alarm is not None:
            return
        if not self.scores:
            raise UserError(f"--calibrate {self.stretch.text}: no scan of --data lies in it.")
        self.det._calibrate_on(np.array(self.scores), self.rate, self.source, learned=True)
        say_calibration(self.det, self.command)
        try:
            self.alarm = parse_alarm(self.policy or "threshold", self.det.threshold_)
        except ValueError as exc:
            raise UserError(f"--alarm: {exc}") from None
