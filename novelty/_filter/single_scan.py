"""One scan at a time, the robot's loop: ``score_learn_one`` and ``score_one`` in one engine call.

The general path of a single scan (:class:`novelty.detector.NoveltyDetector`)
checks the model and the scan, converts, learns a batch of one and checks the
result: tens of microseconds around a scan the compiled engine learns in one
or two. So a filter's ``score_learn_one`` and ``score_one`` first try this
protocol, which gives the same number or leaves the scan to the general path
(None, nothing learned), which then says what is wrong with it:

1. the scan must be a C-contiguous, writable 1-D float64 array, and the filter
   must hold an engine (it makes one on its first general call);
2. under the filter's lock, the engine must be fresh
   (:meth:`~novelty._kernels.interface.Engine.fresh`: nothing set on the
   filter, its unfitted parts or its fitted parts since it was last
   confirmed). When it is not, the general path's checks run once here (the
   parts' parameters after fitting, the filter's parameters, no timestamps,
   calibration over), the engine is had again
   (:func:`novelty._kernels.choice.engine_of`: the state checked, another
   engine chosen if the parts changed) and it is confirmed
   (:meth:`~novelty._kernels.interface.Engine.watch`);
3. the engine learns or scores the scan in one call that checks it (as many
   features as the units, a sum of squares within the norm bound), else
   answers False.
"""

from __future__ import annotations

import numpy as np

from .._kernels.choice import engine_of
from .._kernels.interface import Engine
from ..clusterers.base import Clusterer
from ..detector import _lock_of
from .parts import templates

__all__ = ["learn_one", "score_one"]

#: the type of the scans the single-scan calls take as they are
_FLOAT64 = np.dtype(np.float64)


def learn_one(detector, x: np.ndarray) -> float | None:
    """The novelty of ``x`` before ``detector`` learns it, learned; None (nothing learned) when
    the general path must take it (module docstring)."""
    engine = _candidate(detector, x)
    if engine is None:
        return None
    with _lock_of(detector):
        if vars(detector).get("_engine") is not engine:
            # another thread replaced the engine while this one waited for the lock
            return None
        if not engine.fresh():
            engine = _confirmed(detector)
            if engine is None:
                return None
        if not engine.learn_one(x, float(detector.stimulus)):
            return None
        if detector.novelty_rule == "efficacy":
            out = engine.novelty1.item()
        else:
            out = float(detector._combine(engine.novelty1.copy(), engine.distance1.copy())[0])
        low, high = detector._novelty_interval
        if not low <= out <= high:   # NaN too: the filter's check says whether its synapse allows it
            detector._finite(np.array([out]))
        return out


def score_one(detector, x: np.ndarray) -> float | None:
    """The novelty of ``x`` under ``detector``'s state, without learning; None when the general
    path must take it (module docstring)."""
    engine = _candidate(detector, x)
    if engine is None:
        return None
    with _lock_of(detector):
        if vars(detector).get("_engine") is not engine:
            return None
        if not engine.holds():
            engine = engine_of(detector)
        if not engine.score_one(x):
            return None
        efficacy, distance, row = engine.scored1.tolist()
        if detector.novelty_rule == "efficacy" and type(detector.clusterer_).grows_for is Clusterer.grows_for:
            out = efficacy
        else:
            out = float(detector._novelty_of(np.array([int(row)]), np.array([distance]),
                                             np.array([efficacy]))[0])
        low, high = detector._novelty_interval
        if not low <= out <= high:   # NaN too: the filter's check says whether its synapse allows it
            detector._finite(np.array([out]))
        return out


def _candidate(detector, x: np.ndarray):
    """The detector's engine if ``x`` is a scan the protocol takes as it is (step 1), else None."""
    engine = vars(detector).get("_engine")
    if not isinstance(engine, Engine) or x.ndim != 1 or x.dtype is not _FLOAT64:
        return None  # no engine yet (or a deep copy's CheckedCopy): the general path makes one
    flags = x.flags
    return engine if flags.c_contiguous and flags.writeable else None


def _confirmed(detector):
    """The general path's checks of a learning call, once (module docstring, step 2): the
    engine, confirmed, or None when the scan needs the general path (timestamps, calibrating)."""
    detector._check_online()
    detector._validate_params()
    calibration = detector._calibration
    if detector.last_time_ is not None or not (calibration is None or calibration.full):
        return None
    engine = engine_of(detector)
    engine.watch(detector, *templates(detector))
    return engine
