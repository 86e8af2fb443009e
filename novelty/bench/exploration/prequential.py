"""The exploration protocol: every scan scored, then learned, in order.

Prequential ("predictive sequential") evaluation (Dawid 1984): the detector
meets the scans of an exploration task (:mod:`novelty.tasks.exploration`) in
the order the robot perceived them; each scan's novelty is taken before the
detector may learn it. A suite runs this protocol with
``[suite] protocol = "exploration"``; :func:`evaluate` is then what a cell
computes, on every backend alike.

How each detector learns is its *policy*, set per detector entry
(``policy = "..."``) and shown in its label:

- ``online`` (the default of detectors that learn online): learn every scan
  right after scoring it;
- ``frozen`` (the default of batch-only detectors): learn the warm-up runs,
  then never again. An online detector streams the warm-up; a batch-only one
  is refitted after each warm-up run on the warm-up runs so far;
- ``refit``: refitted from scratch after every run on every run seen so far;
- ``window=N``: refitted after every run on the last ``N`` runs.

Under the refitting policies (and ``frozen`` for batch detectors) a run is
scored by the model of the runs before it; before the first fit nothing is
familiar and every scan scores 1.0, as the first scan of a habituating
filter does. Refitting uses ``fit``, so it applies to any detector.

References
----------
Dawid, A. P. (1984). Statistical theory: the prequential approach. Journal of
the Royal Statistical Society A, 147(2), 278-292.
"""

from __future__ import annotations

import functools
import json
import time
from typing import Callable

import numpy as np

from ...data import FAMILIAR
from ..build import check_input_layout, load_task, make_detector, n_units, resting_novelty
from ..specs import SuiteError
from . import metrics as xm

__all__ = ["POLICIES", "parse_policy", "default_policy", "prequential", "evaluate", "exploration_metrics",
           "EXPLORATION_COLUMNS", "PLACE_COLUMNS", "place_metrics"]

POLICIES = ("online", "frozen", "refit", "window=N")

#: the metric columns of an exploration cell (identical across backends and reruns)
EXPLORATION_COLUMNS = [
    "policy", "n_scans", "n_runs", "warmup_runs", "n_first", "n_recurring",
    "first_encounter_auc", "roc_auc", "excess_1", "excess_2", "excess_3", "habituation_ratio",
    "exposures_to_habituate", "habituated_fraction", "first_separation", "flags_first", "habituates",
    "flags_first_auc_only", "habituates_ratio_only", "return_ratio",
    "threshold", "false_alarms", "false_alarm_rate", "redetection_auc",
    "integrated_novelty", "integrated_per_run", "exposure_curve", "max_novelty", "novelty_range",
    "resting_novelty", "n_units",
]
#: the columns a cell adds when its task says whether each object's place was seen (``seen_place``)
PLACE_COLUMNS = ["n_first_seen", "first_encounter_auc_seen", "n_first_unseen", "first_encounter_auc_unseen"]


def parse_policy(text: str) -> tuple[str, int]:
    """``"window=3"`` -> ``("window", 3)``; ``"refit"`` -> ``("refit", 0)``.

    >>> parse_policy("window=3"), parse_policy("online")
    (('window', 3), ('online', 0))
    """
    if not isinstance(text, str):
        raise SuiteError(f"A policy must be a string, one of {', '.join(POLICIES)}; got {text!r}.")
    kind, sep, value = text.partition("=")
    if kind in ("online", "frozen", "refit") and not sep:
        return kind, 0
    if kind == "window" and sep and value.isdigit() and int(value) >= 1:
        return kind, int(value)
    raise SuiteError(f"Unknown policy {text!r}; expected one of {', '.join(POLICIES)} "
                     "(N a positive int).")


def default_policy(det) -> str:
    """``online`` for a detector that learns online, else ``frozen``."""
    return "online" if getattr(det, "supports_online", True) else "frozen"


def check_policy(policy: str, det) -> None:
    """Refuse a policy the detector cannot follow."""
    kind, _ = parse_policy(policy)
    if kind == "online" and not getattr(det, "supports_online", True):
        raise SuiteError(f"{type(det).__name__} learns in batch only; give it policy 'frozen', "
                         "'refit' or 'window=N'.")


def prequential(make: Callable, X: np.ndarray, run: np.ndarray, warmup: int,
                policy: str = "online") -> tuple[np.ndarray, object]:
    """Novelty of every scan before it is learned, under ``policy``; and the final detector.

    Parameters
    ----------
    make : callable
        Builds a fresh detector (called once, or once a refit).
    X : ndarray of shape (n_scans, n_sensors)
    run : ndarray of shape (n_scans,)
        Run of each scan, in order.
    warmup : int
        Runs ``0 .. warmup - 1`` are the warm-up.
    policy : str, default="online"
    """
    kind, window = parse_policy(policy)
    run = np.asarray(run)
    det = make()
    online = getattr(det, "supports_online", True)
    if kind == "online":
        check_policy(policy, det)
        return np.asarray(det.stream(X), dtype=np.float64), det
    if kind == "frozen" and online:
        warm = run < warmup
        out = np.empty(len(X))
        out[warm] = det.stream(X[warm])
        out[~warm] = det.novelty(X[~warm])
        return out, det
    runs = np.unique(run).tolist()
    out = np.ones(len(X))
    fitted = False
    for i, r in enumerate(runs):
        here = run == r
        if fitted:
            out[here] = det.novelty(X[here])
        last = i == len(runs) - 1
        if last or (kind == "frozen" and r >= warmup):
            continue
        seen = runs[:i + 1] if kind != "window" else runs[max(0, i + 1 - window):i + 1]
        det = make().fit(X[np.isin(run, seen)])
        fitted = True
    return out, det


def evaluate(cell) -> tuple[dict, dict]:
    """What an exploration cell computes: the row of metrics and the per-scan arrays."""
    data = load_task(cell)
    make = functools.partial(make_detector, cell)
    info = data.metadata.get("exploration")
    if info is None or "feature" not in data.columns or data.run is None:
        raise ValueError(f"Task {cell.task.label!r} is not an exploration task (no "
                         "metadata['exploration']); use an exploration-* task or the hold-out protocol.")
    warmup = int(info["warmup_runs"])
    run, feature = np.asarray(data.run), data.columns["feature"].astype(str)
    exposure = np.asarray(data.columns["exposure"])
    probe = make()
    check_input_layout(probe, data, cell.task.label)
    policy = cell.detector.policy or default_policy(probe)
    start = time.perf_counter()
    novelty, det = prequential(make, data.X, run, warmup, policy)
    elapsed = time.perf_counter() - start
    row = exploration_metrics(novelty, run, feature, exposure, warmup, info.get("changes", {}),
                              resting_novelty(det), cell.threshold, info.get("returns", {}))
    row.update({"policy": policy, "n_scans": len(data), "n_runs": int(np.unique(run).size),
                "warmup_runs": warmup, "n_units": n_units(det)})
    if "seen_place" in data.columns:
        row.update(place_metrics(novelty, run, feature, exposure, warmup, data.columns["seen_place"]))
    row.update({"train_time_s": elapsed, "train_scans_per_s": len(data) / max(elapsed, 1e-12)})
    arrays = {"novelty": novelty, "run": run, "feature": feature, "exposure": exposure,
              "environment": data.columns["environment"].astype(str),
              "threshold": np.float64(row["threshold"]), "resting": np.float64(row["resting_novelty"]),
              "warmup": np.int64(warmup)}
    arrays.update(_curve_arrays(xm.exposure_curves(novelty, run, feature, exposure, warmup)))
    return row, arrays


def place_metrics(novelty, run, feature, exposure, warmup: int, seen_place) -> dict:
    """The first-encounter AUC and count of first sights of the objects in seen and in unseen places, apart.

    ``seen_place``: per scan, whether the place of the object it sees was
    seen before the object appeared (:mod:`novelty.tasks.objects.places`).
    """
    seen_place = np.asarray(seen_place, dtype=bool)
    first = (np.asarray(run) >= warmup) & (np.asarray(exposure) == 0) & (np.asarray(feature) != FAMILIAR)
    row = {}
    for name, mask in (("seen", seen_place), ("unseen", ~seen_place)):
        row[f"n_first_{name}"] = int(np.sum(first & mask))
        row[f"first_encounter_auc_{name}"] = xm.first_encounter_auc_of(novelty, run, feature, exposure, warmup, mask)
    return row


def exploration_metrics(novelty, run, feature, exposure, warmup: int, changes: dict,
                        resting: float = 0.0, threshold_rule="max", returns: dict | None = None) -> dict:
    """Every metric of :mod:`novelty.bench.exploration.metrics` for one exploration, as a row."""
    curves = xm.exposure_curves(novelty, run, feature, exposure, warmup)
    recurring = xm.recurring(curves)
    resolution = xm.resolution(novelty)
    to_habituate = [xm.exposures_to_habituate(curves[f]["excess"], resolution=resolution) for f in recurring]
    done = [k for k in to_habituate if not np.isnan(k)]
    threshold = xm.warmup_threshold(novelty, run, warmup, threshold_rule)
    rate, count = xm.false_alarm_rate(novelty, run, feature, warmup, threshold)
    auc = xm.first_encounter_auc(novelty, run, feature, exposure, warmup)
    ratio = xm.habituation_ratio(curves, resolution=resolution)
    longest = max((curves[f]["excess"].size for f in recurring), default=0)
    scored = np.asarray(run) >= warmup
    separation = xm.first_exposure_separation(novelty, run, feature, exposure, warmup)
    separates = bool(separation >= xm.SEPARATES)
    return {
        "n_first": int(np.sum(scored & (np.asarray(exposure) == 0))),
        "n_recurring": len(recurring),
        "first_encounter_auc": auc,
        "roc_auc": auc,
        "excess_1": xm.excess_at(curves, 1), "excess_2": xm.excess_at(curves, 2),
        "excess_3": xm.excess_at(curves, 3),
        "habituation_ratio": ratio,
        "exposures_to_habituate": float(np.mean(done)) if done else float("nan"),
        "habituated_fraction": len(done) / len(recurring) if recurring else float("nan"),
        "first_separation": separation,
        "flags_first": bool(auc >= xm.FLAGS_FIRST) and separates,
        "habituates": xm.habituated(ratio) and separates,
        "flags_first_auc_only": bool(auc >= xm.FLAGS_FIRST),
        "habituates_ratio_only": xm.habituated(ratio),
        "return_ratio": xm.return_ratio(curves, returns or {}),
        "threshold": threshold,
        "false_alarms": count,
        "false_alarm_rate": rate,
        "redetection_auc": xm.redetection_auc(novelty, run, feature, exposure, changes),
        "integrated_novelty": float(np.sum(np.asarray(novelty)[scored] - resting)),
        "integrated_per_run": json.dumps(np.round(xm.integrated_per_run(novelty, run, resting), 6).tolist()),
        "exposure_curve": json.dumps([round(xm.excess_at(curves, k), 6) for k in range(1, longest + 1)]),
        "max_novelty": float(np.max(np.asarray(novelty)[scored])),
        "novelty_range": xm.novelty_range(novelty),
        "resting_novelty": resting,
    }


def _curve_arrays(curves: dict) -> dict:
    """Per-feature exposure curves as plain arrays (rows: features, padded with nan)."""
    names = sorted(curves)
    width = max((curves[f]["excess"].size for f in names), default=0)
    out = {"curve_features": np.array(names, dtype=str)}
    for key in ("novelty", "familiar", "excess"):
        table = np.full((len(names), width), np.nan)
        for i, f in enumerate(names):
            table[i, :curves[f][key].size] = curves[f][key]
        out[f"curve_{key}"] = table
    return out

