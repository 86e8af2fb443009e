"""Checks of parameters and inputs, with one message form for the whole project.

Parameter messages follow scikit-learn's form::

    The 'max_age' parameter of GrowingNeuralGas must be an int in [1, inf). Got 0 instead.

Input checks translate to ``ValueError`` (or ``TypeError`` for sparse input,
as scikit-learn does) *before* any state changes, so a rejected call leaves a
model exactly as it was.

By job: the rules for parameters (:mod:`novelty._validation.parameters`),
scans and their norm bound :data:`MAX_SCAN_NORM`
(:mod:`novelty._validation.scans`), feature names
(:mod:`novelty._validation.names`) and timestamps
(:mod:`novelty._validation.timestamps`); every name is importable from here.
"""

from .names import _dict_values, _name_mismatch, _type_name, check_feature_names, frame_names, scan_names  # noqa: F401
from .parameters import Bounds, Instance, Interval, Options, unknown_parameters, validate_parameters
from .scans import (_MAX_SQUARED_NORM, _NOT_REAL, MAX_SCAN_NORM, _dtype_kinds,  # noqa: F401
                    _refuse_not_real, _too_large, check_batch, check_one)
from .timestamps import check_timestamps, last_timestamp, pass_timestamps

__all__ = [
    "Interval",
    "Options",
    "Instance",
    "Bounds",
    "validate_parameters",
    "unknown_parameters",
    "check_batch",
    "check_one",
    "check_timestamps",
    "last_timestamp",
    "pass_timestamps",
    "scan_names",
    "frame_names",
    "check_feature_names",
    "MAX_SCAN_NORM",
]
