"""Any outlier detector object as a detector of this project: :func:`as_detector`.

- a detector of this project is returned as it is;
- a PyOD detector (a subclass of ``pyod.models.base.BaseDetector``) becomes a
  :class:`~novelty.baselines.PyODDetector` of that object (PyOD's
  ``decision_function``, higher = more abnormal, its parameters as they are);
- a scikit-learn outlier estimator (``fit`` and ``score_samples`` or
  ``decision_function``, higher = more normal) becomes a
  :class:`~novelty.baselines.SklearnOutlierDetector` of it.

So :func:`novelty.bench.run` takes each as it is.
"""

from __future__ import annotations

import numbers

from ..detector import NoveltyDetector
from .pyod_outlier import PyODDetector
from .sklearn_outlier import SklearnOutlierDetector

__all__ = ["as_detector", "is_pyod_detector"]


def is_pyod_detector(obj) -> bool:
    """Whether ``obj`` is a PyOD detector (told by its classes, without importing PyOD)."""
    return any(cls.__name__ == "BaseDetector" and cls.__module__.startswith("pyod.") for cls in type(obj).__mro__)


def as_detector(obj) -> NoveltyDetector:
    """``obj`` as a detector of this project (see the module notes); anything else is a ``TypeError``.

    >>> from sklearn.ensemble import IsolationForest
    >>> type(as_detector(IsolationForest(n_estimators=10))).__name__
    'SklearnOutlierDetector'
    """
    if isinstance(obj, NoveltyDetector):
        return obj
    if is_pyod_detector(obj):
        seed = obj.get_params(deep=False).get("random_state")
        return PyODDetector(model=obj, random_state=seed if isinstance(seed, numbers.Integral) else None)
    if hasattr(obj, "fit") and hasattr(obj, "get_params") and (
            hasattr(obj, "score_samples") or hasattr(obj, "decision_function")):
        return SklearnOutlierDetector(obj)
    raise TypeError(f"{type(obj).__name__} is not an outlier detector: expected a detector of this project, a "
                    "PyOD detector, or a scikit-learn estimator with fit and score_samples or decision_function.")
