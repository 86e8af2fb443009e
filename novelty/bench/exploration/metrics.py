"""Scores of an exploration: is a new feature flagged, and does it become familiar?

Every function takes the novelty of every scan of an exploration, in order
(each scored before it was learned), and the labels of
:mod:`novelty.tasks.exploration`: the run of each scan, its tracked
``feature`` (``""`` for a familiar scan) and its ``exposure`` count (0 at
the feature's first encounter). Warm-up runs (``run < warmup``) are never
scored. Definitions:

- **familiar level** of a run: the mean novelty of its familiar scans (of
  every scored run's familiar scans when the run has none, as in the open
  control area tracked as a whole);
- **excess** of a feature at its k-th exposure (k = 1, 2, ...): the mean
  novelty of its scans in the run of that exposure minus that run's familiar
  level;
- **first-encounter detection**: ROC AUC of the scans at a feature's first
  exposure (positives) against the familiar scans of the runs holding a first
  encounter (negatives);
- **resolution** ``r`` of a detector on an exploration: a millionth
  (``RESOLUTION``) of the range of its novelty over the whole exploration,
  warm-up included: a spread, or a difference, below that is no difference a
  threshold could use;
- **habituation ratio**: over the *recurring* features (met at least three
  times), the mean excess at the 3rd exposure divided by the mean excess at the
  1st; ``nan`` (no verdict) unless the 1st excess is above ``r``: a ratio to
  nothing, or to a first exposure scored below the familiar scans, says
  nothing of habituation. A feature is habituated when the ratio lies in
  ``[-0.25, 0.25]``: its excess has fallen to within a quarter of the first
  one, *on either side* of the familiar level. A 3rd exposure scored far
  below the familiar scans (a ratio of -0.9: as far below as the first was
  above) is still told apart from them, so it is not what this project calls
  habituated. Excesses are differences of novelty, so the ratio, and with it
  the verdict, is the same for ``a * novelty + b`` (any ``a > 0``, any
  ``b``): a detector whose scores are all negative, or on any scale, is
  judged as one whose scores lie in [0, 1];
- **first-encounter detection by place** (:func:`first_encounter_auc_of`):
  the same, of the objects whose place was seen before they appeared and of
  those whose place was not, apart (a task's ``seen_place`` column);
- **first-exposure separation**: how far the typical first-exposure scan
  lies above the typical familiar scan, in units of the familiar scans'
  spread: ``(median(first) - median(familiar)) / max(IQR(familiar), r)``,
  over the scans of the first-encounter detection, with ``r`` the
  detector's resolution (a detector whose every scan lies below 1e-35 would
  otherwise separate by ratios of numbers near 1e-151). It does not depend
  on the detector's scale (``a * novelty + b`` gives the same). A detector
  **flags** first encounters when the first-encounter ROC AUC is at least
  0.85 *and* the separation at least 0.5, and **habituates** when the
  habituation ratio lies within 0.25 of 0 *and* the separation is at least
  0.5: ranks decided by differences far below the
  familiar scans' own spread (a network whose every scan sits at its
  synapses' floor, its first encounters lifted by the few scans that add a
  unit) neither flag nor habituate;
- **return ratio**: for a feature that comes back after a long absence
  (``returns``: the exposure of its return), its excess at the return over
  its excess at the first exposure: near 1 a detector that forgot it, near
  its habituated level one that remembers;
- **exposures to habituate** of a feature: the first exposure k at which its
  excess lies within ``tolerance`` (default 0.25, the same quarter) times its
  first-exposure excess of the familiar level, on either side; ``nan`` if that
  never happens within its exposures or the first exposure was not above the
  familiar level by more than ``r``;
- **false-alarm rate**: the share of the familiar scans of the scored runs
  whose novelty is strictly above a threshold set from the last warm-up run
  (:func:`novelty.bench.holdout.metrics.training_threshold` of its novelty);
- **re-detection**: for a feature that replaced an earlier one at the same
  place (``changes``), the ROC AUC of its first-exposure scans against the
  familiar scans of the same run;
- **integrated novelty per run**: the paper's Table 1 measure,
  ``sum (novelty - resting)`` over each run (Marsland et al., 2000).

Shares its name with ``novelty/bench/holdout/metrics.py``, ``novelty/metrics.py``: each benchmark
protocol's package holds its own metrics, plots and summary; novelty/metrics.py is the users' ROC
AUC of novelty scores.
"""

from __future__ import annotations

import math

import numpy as np

from ...data import FAMILIAR
from ..holdout import metrics as bench_metrics

__all__ = ["familiar_levels", "exposure_curves", "first_encounter_auc", "first_encounter_auc_of", "excess_at",
           "habituation_ratio", "exposures_to_habituate", "false_alarm_rate", "redetection_auc",
           "integrated_per_run", "warmup_threshold", "recurring", "first_exposure_separation", "return_ratio",
           "resolution", "novelty_range", "habituated", "ratio_to_first", "HABITUATED", "FLAGS_FIRST", "RECURRING", "SEPARATES", "RESOLUTION"]

#: An excess within this share of the first-exposure excess (either side of the familiar level) is habituated.
HABITUATED = 0.25
#: A first-encounter ROC AUC at least this flags first encounters.
FLAGS_FIRST = 0.85
#: A feature is recurring when it is met at least this many times.
RECURRING = 3
#: The least first-exposure separation (in familiar IQRs) with which AUC and ratio count.
SEPARATES = 0.5
#: The share of the detector's own range of novelty below which a spread counts as none.
RESOLUTION = 1e-6


def _arrays(novelty, run, feature, exposure=None):
    novelty = np.asarray(novelty, dtype=np.float64)
    run = np.asarray(run)
    feature = np.asarray(feature).astype(str)
    n = novelty.shape[0]
    for name, a in (("run", run), ("feature", feature)) + ((("exposure", np.asarray(exposure)),)
                                                            if exposure is not None else ()):
        if a.shape != (n,):
            raise ValueError(f"{name} has shape {a.shape}; expected ({n},), one value a scan.")
    return novelty, run, feature


def familiar_levels(novelty, run, feature, warmup: int) -> dict[int, float]:
    """``{run: familiar level}`` of every scored run (see the module docstring)."""
    novelty, run, feature = _arrays(novelty, run, feature)
    scored = run >= warmup
    familiar = scored & (feature == FAMILIAR)
    overall = float(novelty[familiar].mean()) if familiar.any() else float("nan")
    levels = {}
    for r in np.unique(run[scored]).tolist():
        here = familiar & (run == r)
        levels[r] = float(novelty[here].mean()) if here.any() else overall
    return levels


def exposure_curves(novelty, run, feature, exposure, warmup: int) -> dict[str, dict[str, np.ndarray]]:
    """Per tracked feature, its novelty, familiar level and excess at each exposure.

    Returns ``{feature: {"novelty": a, "familiar": b, "excess": a - b, "run": runs}}``,
    index k - 1 for the k-th exposure.

    >>> nov = [0.9, 0.1, 0.5, 0.1, 0.2, 0.1]
    >>> c = exposure_curves(nov, [1, 1, 2, 2, 3, 3], ["d", "", "d", "", "d", ""], [0, -1, 1, -1, 2, -1], 1)
    >>> np.round(c["d"]["excess"], 2).tolist()
    [0.8, 0.4, 0.1]
    """
    novelty, run, feature = _arrays(novelty, run, feature, exposure)
    exposure = np.asarray(exposure)
    levels = familiar_levels(novelty, run, feature, warmup)
    curves = {}
    scored = run >= warmup
    for f in sorted(set(feature[scored & (feature != FAMILIAR)].tolist())):
        mine = scored & (feature == f)
        ks = np.unique(exposure[mine])
        nov, fam, runs = [], [], []
        for k in ks.tolist():
            here = mine & (exposure == k)
            r = int(run[here][0])
            nov.append(float(novelty[here].mean()))
            fam.append(levels[r])
            runs.append(r)
        nov, fam = np.array(nov), np.array(fam)
        curves[f] = {"novelty": nov, "familiar": fam, "excess": nov - fam, "run": np.array(runs),
                     "exposure": ks + 1}
    return curves


def first_encounter_auc(novelty, run, feature, exposure, warmup: int) -> float:
    """ROC AUC of first-exposure scans against familiar scans of the same runs.

    >>> first_encounter_auc([0.9, 0.2, 0.4, 0.3], [1, 1, 2, 2], ["d", "", "d", ""], [0, -1, 1, -1], 1)
    1.0
    """
    novelty, run, feature = _arrays(novelty, run, feature, exposure)
    exposure = np.asarray(exposure)
    scored = run >= warmup
    first = scored & (exposure == 0) & (feature != FAMILIAR)
    runs = np.unique(run[first])
    familiar = scored & (feature == FAMILIAR) & np.isin(run, runs)
    keep = first | familiar
    return bench_metrics.roc_auc(novelty[keep], first[keep])


def first_encounter_auc_of(novelty, run, feature, exposure, warmup: int, mask) -> float:
    """:func:`first_encounter_auc` of the features whose scans ``mask`` holds (the others' scans left out).

    ``mask``: per scan, whether its feature is one of those kept (familiar
    scans are kept whatever it says). Used for the objects in seen and in
    unseen places (a task's ``seen_place`` column).

    >>> nov, run = [0.9, 0.2, 0.1, 0.4, 0.3], [1, 1, 1, 2, 2]
    >>> first_encounter_auc_of(nov, run, ["d", "", "e", "d", ""], [0, -1, 0, 1, -1], 1, [1, 0, 0, 1, 0])
    1.0
    >>> first_encounter_auc_of(nov, run, ["d", "", "e", "d", ""], [0, -1, 0, 1, -1], 1, [0, 0, 1, 0, 0])
    0.0
    """
    novelty, run, feature = _arrays(novelty, run, feature, exposure)
    mask = np.asarray(mask, dtype=bool)
    if mask.shape != novelty.shape:
        raise ValueError(f"mask has shape {mask.shape}; expected ({novelty.size},), one value a scan.")
    kept = mask | (feature == FAMILIAR)
    return first_encounter_auc(novelty[kept], run[kept], feature[kept], np.asarray(exposure)[kept], warmup)


def first_exposure_separation(novelty, run, feature, exposure, warmup: int) -> float:
    """``(median(first) - median(familiar)) / max(IQR(familiar), r)`` over the scans of the first-encounter AUC.

    ``r`` is ``RESOLUTION`` times the range of ``novelty`` (every scan given,
    warm-up included; module docstring). Familiar 0.1, 0.2, 0.3, 0.4 (median
    0.25, IQR 0.325 - 0.175), first 0.8, 0.9:

    >>> s = first_exposure_separation([0.9, 0.1, 0.3, 0.8, 0.2, 0.4], [1] * 6, ["d", "", "", "d", "", ""],
    ...                               [0, -1, -1, 0, -1, -1], 1)
    >>> round(s, 9)
    4.0
    """
    novelty, run, feature = _arrays(novelty, run, feature, exposure)
    exposure = np.asarray(exposure)
    scored = run >= warmup
    first = scored & (exposure == 0) & (feature != FAMILIAR)
    familiar = scored & (feature == FAMILIAR) & np.isin(run, np.unique(run[first]))
    if not first.any() or not familiar.any():
        return float("nan")
    q25, q50, q75 = np.percentile(novelty[familiar], [25, 50, 75])
    above = float(np.median(novelty[first]) - q50)
    spread = max(float(q75 - q25), resolution(novelty))
    if spread > 0:
        return above / spread
    return 0.0  # every scan scored alike: nothing is separated


def resolution(novelty) -> float:
    """``RESOLUTION`` times the range of the finite values of ``novelty`` (every scan of the exploration).

    >>> resolution([0.5, -1.5, np.inf, 2.5])
    4e-06
    """
    return RESOLUTION * novelty_range(novelty)


def novelty_range(novelty) -> float:
    """The range (max - min) of the finite values of ``novelty``; 0 if none is finite."""
    novelty = np.asarray(novelty, dtype=np.float64)
    finite = novelty[np.isfinite(novelty)]
    return float(finite.max() - finite.min()) if finite.size else 0.0


def return_ratio(curves: dict, returns: dict) -> float:
    """Mean over the returning features of the excess at their return over the excess at their first exposure.

    >>> return_ratio({"d": {"excess": np.array([0.8, 0.2, 0.1, 0.4]), "exposure": np.arange(1, 5)}}, {"d": 4})
    0.5
    """
    values = []
    for f, k in sorted(returns.items()):
        c = curves.get(f)
        if c is None or k not in c["exposure"].tolist() or 1 not in c["exposure"].tolist():
            continue
        first = c["excess"][c["exposure"].tolist().index(1)]
        if first > 0:
            values.append(c["excess"][c["exposure"].tolist().index(k)] / first)
    return float(np.mean(values)) if values else float("nan")


def recurring(curves: dict, min_exposures: int = RECURRING) -> list[str]:
    return [f for f, c in curves.items() if c["excess"].size >= min_exposures
            and np.array_equal(c["exposure"][:min_exposures], np.arange(1, min_exposures + 1))]


def excess_at(curves: dict, k: int, min_exposures: int = RECURRING) -> float:
    """Mean excess at the k-th exposure over the recurring features (``nan`` if none)."""
    values = [curves[f]["excess"][k - 1] for f in recurring(curves, min_exposures)
              if curves[f]["excess"].size >= k]
    return float(np.mean(values)) if values else float("nan")


def habituation_ratio(curves: dict, k: int = RECURRING, resolution: float = 0.0) -> float:
    """Mean excess at the k-th exposure over the mean at the first, recurring features only.

    ``nan`` when no feature recurs or the first exposures were not above the
    familiar level by more than ``resolution`` on average (the detector's
    resolution, :func:`resolution`: a ratio to nothing is no ratio).
    """
    first, later = excess_at(curves, 1, k), excess_at(curves, k, k)
    return ratio_to_first(later, first, resolution)


def ratio_to_first(later: float, first: float, resolution: float = 0.0) -> float:
    """``later / first``, or ``nan`` unless ``first`` is above ``resolution`` (and above 0)."""
    if math.isnan(first) or first <= max(resolution, 0.0):
        return float("nan")
    return later / first


def habituated(ratio: float, tolerance: float = HABITUATED) -> bool:
    """Whether a habituation ratio lies within ``tolerance`` of 0, on either side (``nan``: no).

    >>> habituated(0.1), habituated(-0.1), habituated(-0.9), habituated(float("nan"))
    (True, True, False, False)
    """
    return bool(abs(ratio) <= tolerance)


def exposures_to_habituate(excess, tolerance: float = HABITUATED, resolution: float = 0.0) -> float:
    """First exposure (1-based) whose excess lies within ``tolerance`` x the first one's of 0, either side.

    ``nan`` if none does, or if the first excess is not above ``resolution``
    (and 0).

    >>> exposures_to_habituate([0.8, 0.4, 0.1])
    3.0
    >>> exposures_to_habituate([0.8, 0.7, 0.6])
    nan
    >>> exposures_to_habituate([0.8, -0.7, 0.1])  # -0.7: told apart from the familiar scans still
    3.0
    """
    excess = np.asarray(excess, dtype=np.float64)
    if excess.size == 0 or not excess[0] > max(resolution, 0.0):
        return float("nan")
    hit = np.flatnonzero(np.abs(excess) <= tolerance * excess[0])
    return float(hit[0] + 1) if hit.size else float("nan")


def warmup_threshold(novelty, run, warmup: int, rule="max") -> float:
    """The alarm threshold from the novelty of the last warm-up run (its max, or a quantile)."""
    novelty = np.asarray(novelty, dtype=np.float64)
    return bench_metrics.training_threshold(novelty[np.asarray(run) == warmup - 1], rule)


def false_alarm_rate(novelty, run, feature, warmup: int, threshold: float) -> tuple[float, int]:
    """(rate, count) of familiar scans of the scored runs above ``threshold``.

    >>> false_alarm_rate([0.9, 0.1, 0.5, 0.7], [0, 1, 1, 1], ["", "", "", "d"], 1, 0.4)
    (0.5, 1)
    """
    novelty, run, feature = _arrays(novelty, run, feature)
    familiar = (run >= warmup) & (feature == FAMILIAR)
    count = bench_metrics.count_alarms(novelty[familiar], threshold)
    return (float(count / familiar.sum()) if familiar.any() else float("nan")), count


def redetection_auc(novelty, run, feature, exposure, changes: dict) -> float:
    """Mean over changed features of the ROC AUC of their first exposure against familiar scans of that run."""
    novelty, run, feature = _arrays(novelty, run, feature, exposure)
    exposure = np.asarray(exposure)
    values = []
    for new in sorted(changes):
        first = (feature == new) & (exposure == 0)
        if not first.any():
            continue
        r = run[first][0]
        keep = first | ((run == r) & (feature == FAMILIAR))
        values.append(bench_metrics.roc_auc(novelty[keep], first[keep]))
    values = [v for v in values if not math.isnan(v)]
    return float(np.mean(values)) if values else float("nan")


def integrated_per_run(novelty, run, resting: float = 0.0) -> np.ndarray:
    """The paper's integrated novelty of every run, in run order.

    >>> integrated_per_run([1.0, 0.5, 0.2, 0.2], [0, 0, 1, 1], resting=0.1).round(2).tolist()
    [1.3, 0.2]
    """
    novelty = np.asarray(novelty, dtype=np.float64)
    run = np.asarray(run)
    return np.array([bench_metrics.integrated_novelty(novelty[run == r], resting)
                     for r in np.unique(run)])
