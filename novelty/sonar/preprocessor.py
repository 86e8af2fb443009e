"""The paper's sonar preprocessing as a scikit-learn transformer.

``SonarPreprocessor(threshold=4.0)`` turns ranges in metres into the inputs
of the paper's novelty filter, ``1 - min(r, threshold) / threshold``
(Marsland et al., 2000, section 4.1; :func:`novelty.sonar.preprocess`), so
that raw sonar readings go through a ``Pipeline`` before any detector. The
paper's other step, averaging over each 10 cm of travel (section 4.2), needs
the distance travelled at each scan, which a transformer is not given: it is
:func:`novelty.sonar.bin_by_distance`, or ``bin_length`` of the ``files``
task and of ``novelty run``.

Kept apart from :mod:`novelty.sonar.preprocessing` so that the simulator and
the command line do not import scikit-learn to preprocess.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted, validate_data

from .._validation import Interval, validate_parameters
from .preprocessing import PAPER_THRESHOLD, preprocess

__all__ = ["SonarPreprocessor"]


class SonarPreprocessor(TransformerMixin, BaseEstimator):
    """Threshold, normalise and invert sonar ranges: ``1 - min(r, threshold) / threshold``.

    A range at or beyond ``threshold`` (and ``inf``, no echo) becomes 0, a
    contact 1: closer objects give larger inputs, every value in [0, 1].
    Stateless: ``fit`` only checks the parameters and learns the number of
    sensors.

    Parameters
    ----------
    threshold : float, default=4.0
        The range (m) mapped to 0; the paper's "about 4 metres".

    Attributes
    ----------
    n_features_in_ : int
        Number of sensors seen in ``fit``.

    References
    ----------
    Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
    of an environment using habituation. Proc. SAB 2000, section 4.1.

    Examples
    --------
    >>> from sklearn.pipeline import make_pipeline
    >>> import novelty
    >>> pipe = make_pipeline(SonarPreprocessor(), novelty.make("hsom", n_rows=3))
    >>> SonarPreprocessor().fit_transform([[0.0, 1.0, 2.0, 6.5]]).tolist()
    [[1.0, 0.75, 0.5, 0.0]]
    >>> pipe.fit([[1.0, 2.0, 3.0]]).predict([[1.0, 2.0, 3.0]]).shape
    (1,)
    """

    _parameter_rules = {"threshold": Interval(numbers.Real, 0, None, closed="neither")}

    def __init__(self, threshold: float = PAPER_THRESHOLD):
        self.threshold = threshold

    def fit(self, X, y=None):
        """Check the parameters and the ranges; learn the number of sensors."""
        validate_parameters(self)
        self._ranges(X, reset=True)
        return self

    def transform(self, X):
        """The preprocessed ranges, an array of the same shape in [0, 1]."""
        check_is_fitted(self)
        return preprocess(self._ranges(X, reset=False), self.threshold)

    def get_feature_names_out(self, input_features=None):
        """The sensors' names, unchanged (``x0, x1, ...`` without names)."""
        check_is_fitted(self)
        if input_features is not None:
            return np.asarray(input_features, dtype=object)
        names = getattr(self, "feature_names_in_", None)
        return names if names is not None else np.array([f"x{i}" for i in range(self.n_features_in_)],
                                                        dtype=object)

    def _ranges(self, X, reset: bool) -> np.ndarray:
        X = validate_data(self, X, reset=reset, dtype=np.float64, ensure_all_finite=False)
        if np.isnan(X).any():
            raise ValueError(f"{type(self).__name__} expects ranges in metres (inf for no echo); "
                             "got NaN.")
        return X

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.requires_fit = True
        tags.input_tags.allow_nan = False
        return tags
