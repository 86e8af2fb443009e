"""Baseline novelty detectors the habituating filter is compared with.

One module per detector, each a :class:`~novelty.detector.NoveltyDetector`
registered by name, all reporting novelty on the comparable [0, 1] scale of
:mod:`novelty.baselines._calibration` (``raw_novelty`` gives each one's own
score). Modules are imported on first use, like the registry's built-ins.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = [
    "CalibratedDetector",
    "comparable",
    "KohonenNoveltyFilter",
    "AutoencoderFilter",
    "GaussianMixtureDetector",
    "SOMDistance",
    "NearestMemory",
    "KNNDetector",
    "OccupancyGrid",
    "ParzenDetector",
    "SklearnOutlierDetector",
    "IsolationForestDetector",
    "OneClassSVMDetector",
    "LocalOutlierFactorDetector",
    "EllipticEnvelopeDetector",
    "PyODDetector",
    "as_detector",
]

_MODULES = {
    "CalibratedDetector": "_calibration",
    "comparable": "_calibration",
    "KohonenNoveltyFilter": "kohonen",
    "AutoencoderFilter": "autoencoder",
    "GaussianMixtureDetector": "gmm",
    "SOMDistance": "som_distance",
    "NearestMemory": "nearest_memory",
    "KNNDetector": "knn",
    "OccupancyGrid": "occupancy_grid",
    "ParzenDetector": "parzen",
    "SklearnOutlierDetector": "sklearn_outlier",
    "IsolationForestDetector": "sklearn_outlier",
    "OneClassSVMDetector": "sklearn_outlier",
    "LocalOutlierFactorDetector": "sklearn_outlier",
    "EllipticEnvelopeDetector": "sklearn_outlier",
    "PyODDetector": "pyod_outlier",
    "as_detector": "wrapping",
}


def __getattr__(name: str) -> Any:
    if name in _MODULES:
        value = getattr(importlib.import_module(f"{__name__}.{_MODULES[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
