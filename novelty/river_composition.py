"""River's own composition for every detector: pipelines, progressive validation, River's metrics.

River users compose and evaluate an anomaly detector with River's tools
(Montiel et al. 2021)::

    model = preprocessing.MinMaxScaler() | novelty.make("hsom")
    evaluate.progressive_val_score(stream, model, metrics.ROCAUC())

What River asks of the last step of such a pipeline, and how a detector of
this project answers:

- ``_supervised``: False (a detector learns from ``x`` alone);
  :class:`~novelty.detector.NoveltyDetector` says so as a class attribute;
- being a ``river.base.AnomalyDetector``: River tells an anomaly detector
  from a classifier by ``isinstance`` (its progressive validation then calls
  ``score_one`` before ``learn_one``, and ``ROCAUC.works_with`` accepts it).
  :func:`register_with_river` registers the detector base class as a virtual
  subclass of River's (the public ``abc`` mechanism River's base class is
  built on) when River is installed; it is called once, as
  :mod:`novelty.detector` is imported;
- ``score_one(x)`` and ``learn_one(x)`` on dicts: the detector's own. A
  pipeline scores its first scan before anything is learned, when River's
  scalers still give NaN for every feature; a detector that has learned
  nothing answers the novelty of a first perception whatever the values,
  so a scan of NaN only is accepted then (and only then).

``learn_one`` returns the detector, as River's ``check_learn_one`` expects of
"the calling model"; River's own pipelines and evaluation ignore what it
returns (River 0.26).

References
----------
Montiel, J. et al. (2021). River: machine learning for streaming data in
Python. Journal of Machine Learning Research, 22(110), 1-8.
"""

from __future__ import annotations

import importlib.util
import math

__all__ = ["register_with_river", "unlearned_river_scan"]


def register_with_river(detector_class: type) -> bool:
    """Register ``detector_class`` as a River anomaly detector if River is installed (True if it was).

    River is an optional dependency; importing ``river.base`` after this
    package's own imports has a cost (docs/guide/performance.md), paid only
    where River is installed.
    """
    if importlib.util.find_spec("river") is None:
        return False
    from river import base  # optional dependency, imported only where it is installed

    base.AnomalyDetector.register(detector_class)
    return True


def unlearned_river_scan(x) -> bool:
    """Whether ``x`` is a scan of NaN only, as River's scalers give before they have learned anything.

    >>> unlearned_river_scan({"a": float("nan"), "b": float("nan")}), unlearned_river_scan({"a": 0.5})
    (True, False)
    """
    return isinstance(x, dict) and bool(x) and all(isinstance(v, float) and math.isnan(v) for v in x.values())
