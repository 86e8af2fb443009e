"""Laser scans to the paper's ring as a scikit-learn transformer: :class:`LaserSectors`.

``LaserSectors`` does steps 1 and 2 of :mod:`novelty.io.scans` (invalid
readings, sectors) on rows of raw ranges; chained with
:class:`novelty.sonar.SonarPreprocessor` (threshold, normalise, invert) it
turns a recorded laser into the inputs of the paper's filter inside a
``Pipeline``. Kept apart from :mod:`novelty.io.scans` so that the readers do
not import scikit-learn.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from ..._validation import Bounds, Interval, Options, validate_parameters
from .sectors import REDUCTIONS, _check_reduce, reduce_sectors, sector_index
from .ranges import clean_ranges

__all__ = ["LaserSectors"]


class LaserSectors(TransformerMixin, BaseEstimator):
    """Reduce each row of laser ranges to ``n_sectors`` ranges, one per equal angular sector.

    Parameters
    ----------
    n_sectors : int, default=16
        Sectors (the paper's robot: 16 sonars).
    reduce : {"min", "mean", "median"} or float, default="min"
        How a sector's valid beams become one range; a number q takes the
        q-th percentile. ``"min"`` is a sonar's nearest echo.
    angle_min, angle_increment : float, optional
        The first beam's angle and the beams' spacing (rad). Default: a
        180-degree scan, the first beam at -pi/2 (the robot's right).
    range_min, range_max : float, default=0.0, inf
        The sensor's valid range (m): finite readings outside it carry no
        information (:func:`novelty.io.scans.ranges.clean_ranges`).
    limits : (float, float), optional
        The span (rad from the front) cut into sectors; default the scan's.
    front : float, default=0.0
        The angle (rad) of the robot's front in the scan's frame.
    clip : float, optional
        Ranges beyond ``clip`` (m) count as ``clip`` before reducing.

    Attributes
    ----------
    n_features_in_ : int
        Beams per scan.
    sector_of_beam_ : ndarray of shape (n_beams,)
        Each beam's sector, -1 outside ``limits``.

    References
    ----------
    Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
    of an environment using habituation. Proc. SAB 2000, section 4.1 (16
    sonars). REP 117 for invalid readings.

    Examples
    --------
    >>> from sklearn.pipeline import make_pipeline
    >>> from novelty.sonar import SonarPreprocessor
    >>> ranges = [[1.0, 3.0, float("inf"), 2.0]]
    >>> LaserSectors(n_sectors=2).fit_transform(ranges).tolist()
    [[1.0, 2.0]]
    >>> make_pipeline(LaserSectors(n_sectors=2), SonarPreprocessor(4.0)).fit_transform(ranges).tolist()
    [[0.75, 0.5]]
    """

    _parameter_rules = {
        "n_sectors": Interval(numbers.Integral, 1, None),
        "reduce": (Options(REDUCTIONS), Interval(numbers.Real, 0, 100)),
        "angle_min": Interval(numbers.Real, -2 * math.pi, 2 * math.pi, allow_none=True),
        "angle_increment": Interval(numbers.Real, 0, math.pi, closed="right", allow_none=True),
        "range_min": Interval(numbers.Real, 0, None),
        "range_max": (Interval(numbers.Real, 0, None, closed="neither"), Options((math.inf,))),
        "limits": (Bounds(), Options((None,))),
        "front": Interval(numbers.Real, -2 * math.pi, 2 * math.pi),
        "clip": Interval(numbers.Real, 0, None, closed="neither", allow_none=True),
    }

    def __init__(self, n_sectors: int = 16, reduce="min", angle_min=None, angle_increment=None,
                 range_min: float = 0.0, range_max: float = math.inf, limits=None, front: float = 0.0,
                 clip=None):
        self.n_sectors = n_sectors
        self.reduce = reduce
        self.angle_min = angle_min
        self.angle_increment = angle_increment
        self.range_min = range_min
        self.range_max = range_max
        self.limits = limits
        self.front = front
        self.clip = clip

    def fit(self, X, y=None):
        """Check the parameters; place every beam in its sector."""
        validate_parameters(self)
        _check_reduce(self.reduce)
        X = validate_data(self, X, reset=True, dtype=np.float64, ensure_all_finite=False,
                          ensure_min_features=2)
        n = X.shape[1]
        start = -math.pi / 2 if self.angle_min is None else self.angle_min
        step = math.pi / (n - 1) if self.angle_increment is None else self.angle_increment
        self.sector_of_beam_ = sector_index(start + step * np.arange(n), self.n_sectors, self.limits,
                                            self.front)
        return self

    def transform(self, X):
        """The rings: an array of shape (n_scans, n_sectors), ``+inf`` where a sector saw nothing."""
        check_is_fitted(self)
        X = validate_data(self, X, reset=False, dtype=np.float64, ensure_all_finite=False)
        ranges = clean_ranges(X, self.range_min, self.range_max)
        return reduce_sectors(ranges, self.sector_of_beam_, self.n_sectors, self.reduce, self.clip)

    def get_feature_names_out(self, input_features=None):
        """``sector0 .. sector{n-1}``, counter-clockwise from the first sector."""
        check_is_fitted(self)
        return np.array([f"sector{k}" for k in range(self.n_sectors)], dtype=object)

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.requires_fit = True
        tags.input_tags.allow_nan = True
        return tags
