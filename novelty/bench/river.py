"""River's streaming anomaly detectors in the benchmark, by name (optional extra ``river``).

So that users see the streaming detectors they know in the same table, a
suite may name:

- ``river-hst``: ``river.anomaly.HalfSpaceTrees`` (Tan, Ting & Liu 2011);
- ``river-loda``: ``river.anomaly.LODA`` (Pevny 2016);
- ``river-lof``: ``river.anomaly.LocalOutlierFactor``, incremental
  (Pokrajac, Lazarevic & Latecki 2007).

``params`` go to the River class; ``random_state`` becomes River's ``seed``
where the class takes one. Each scan is passed as ``{sensor index: value}``;
its novelty is River's ``score_one`` (higher = more anomalous, as here).
Sonar scans lie in [0, 1], the range ``HalfSpaceTrees`` assumes by default.

These adapters are for the benchmark only: they are not registered detectors
(a River model cannot be written to this project's pickle-free model files),
and :func:`is_river` / :func:`make` are what the suite and the cell call for
these names.

References
----------
Montiel, J. et al. (2021). River: machine learning for streaming data in
Python. Journal of Machine Learning Research, 22(110), 1-8.
"""

from __future__ import annotations

import importlib.util
import inspect

import numpy as np

from ..detector import NoveltyDetector

__all__ = ["RIVER_MODELS", "RiverDetector", "is_river", "installed", "make"]

#: benchmark name -> class of ``river.anomaly``
RIVER_MODELS = {
    "river-hst": "HalfSpaceTrees",
    "river-loda": "LODA",
    "river-lof": "LocalOutlierFactor",
}


def is_river(name: str) -> bool:
    """Whether ``name`` is one of the River adapters' names."""
    return name in RIVER_MODELS


def installed() -> bool:
    """Whether the ``river`` package can be imported."""
    return importlib.util.find_spec("river") is not None


def make(name: str, **params) -> "RiverDetector":
    """The adapter called ``name``; ``params`` go to the River class (``random_state``, ``threshold`` to the adapter)."""
    if name not in RIVER_MODELS:
        raise ValueError(f"Unknown River detector {name!r}; known: {', '.join(RIVER_MODELS)}.")
    own = {k: params.pop(k) for k in ("random_state", "threshold") if k in params}
    return RiverDetector(model=RIVER_MODELS[name], params=params, **own)


def _river_class(model: str):
    try:
        from river import anomaly  # optional dependency: imported only when a River detector runs
    except ImportError:
        raise ImportError("River detectors need the 'river' package: "
                          "pip install 'novelty-habituation[river]'.") from None
    cls = getattr(anomaly, model, None)
    if cls is None:
        raise ValueError(f"river.anomaly has no {model!r}.")
    return cls


class RiverDetector(NoveltyDetector):
    """A River anomaly detector, scored then learned one scan at a time.

    Parameters
    ----------
    model : str, default="HalfSpaceTrees"
        A class of ``river.anomaly``.
    params : dict, optional
        Its parameters.
    random_state : int or None, default=None
        River's ``seed``, where the class takes one.
    threshold : float, default=0.5
        Scans scoring above it are called novel (``predict``).

    Attributes
    ----------
    model_ : river.anomaly.base.AnomalyDetector
        The River model.
    """

    def __init__(self, model="HalfSpaceTrees", params=None, random_state=None, threshold=0.5):
        self.model = model
        self.params = params
        self.random_state = random_state
        self.threshold = threshold

    def _validate_params(self) -> None:
        super()._validate_params()
        cls = _river_class(self.model)
        valid = inspect.signature(cls).parameters
        unknown = sorted(set(self.params or {}) - set(valid))
        if unknown:
            raise ValueError(f"river.anomaly.{self.model} has no parameter {unknown[0]!r}; it takes "
                             f"{', '.join(valid)}.")

    def _start(self, X: np.ndarray) -> None:
        cls = _river_class(self.model)
        params = dict(self.params or {})
        if "seed" in inspect.signature(cls).parameters and self.random_state is not None:
            params.setdefault("seed", int(self.random_state))
        self.model_ = cls(**params)

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        out = np.empty(X.shape[0])
        for i, row in enumerate(X):
            x = dict(enumerate(row.tolist()))
            out[i] = self.model_.score_one(x)
            self.model_.learn_one(x)
        return out

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        return np.array([self.model_.score_one(dict(enumerate(row.tolist()))) for row in X])
