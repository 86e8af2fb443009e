"""A Parzen-window (kernel) density of the familiar inputs; novelty = -log density.

With the n familiar inputs ``x_i`` in d dimensions and a Gaussian kernel of
bandwidth ``h``,

    p(x) = 1/n sum_i (2 pi h^2)^(-d/2) exp(-||x - x_i||^2 / (2 h^2))      (1)

(Parzen 1962), the density scikit-learn's ``KernelDensity(kernel="gaussian",
bandwidth=h)`` computes. The raw novelty is ``-log p(x)``, evaluated here in
the log domain (log-sum-exp), so that inputs far from every sample keep a
finite, ordered score.

The bandwidth is one of the normal-reference rules for an isotropic kernel,
with ``sigma^2`` the mean of the features' sample variances (1 if all are 0):

- ``"scott"``:     h = sigma * n^(-1 / (d + 4))                           (2)
- ``"silverman"``: h = sigma * (4 / (d + 2))^(1 / (d + 4)) * n^(-1 / (d + 4))   (3)

or a given positive number. The rules assume roughly normal, similarly scaled
features; scale the inputs first otherwise.

The comparable scale (:mod:`novelty.baselines._calibration`) is calibrated
on leave-one-out scores of the training inputs (each one's density from the
other n - 1), which are not biased low as in-sample scores are, where every
input sits on its own kernel.

Model files hold the training inputs (``samples_``) and ``bandwidth_``, which
define the model entirely: saving is supported. The model grows with the
training set (n x d floats).

References
----------
Parzen, E. (1962). On estimation of a probability density function and mode.
Annals of Mathematical Statistics, 33(3), 1065-1076.

Scott, D. W. (1992). Multivariate Density Estimation. Wiley (rule 2).

Silverman, B. W. (1986). Density Estimation for Statistics and Data
Analysis. Chapman & Hall (rule 3).

Bishop, C. M. (1994). Novelty detection and neural network validation. IEE
Proceedings - Vision, Image and Signal Processing, 141(4), 217-222.
"""

from __future__ import annotations

import numbers

import numpy as np
from scipy.special import logsumexp

from .._component import StateError, check_array_state
from .._validation import Interval, Options, check_batch
from ._calibration import CalibratedDetector

__all__ = ["ParzenDetector"]

#: distances computed per block (rows x samples), to bound memory
_BLOCK = 1 << 20


class ParzenDetector(CalibratedDetector):
    """Parzen-window density with a Gaussian kernel: novelty = -log p(x).

    Parameters
    ----------
    bandwidth : {"scott", "silverman"} or float, default="scott"
        The kernel width h: a rule (equations 2-3) or a positive number.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    samples_ : ndarray of shape (n_samples, n_features)
        The training inputs (the kernel centres).
    bandwidth_ : float
        The bandwidth used.
    reference_ : ndarray
        Calibration of the comparable scale (leave-one-out scores).

    References
    ----------
    Parzen (1962); Scott (1992); Silverman (1986); Bishop (1994).

    Examples
    --------
    >>> import numpy as np
    >>> X = np.random.default_rng(0).normal(size=(200, 2))
    >>> det = ParzenDetector().fit(X)
    >>> round(det.bandwidth_, 2)        # sigma * 200 ** (-1 / 6)
    0.41
    >>> bool(det.novelty([[6.0, 6.0]])[0] > 0.99)
    True
    """

    _scores_itself = True  # a training scan's own kernel: leave-one-out for the scale
    _parameter_rules = {
        # h^2 and the squared distances of scans of norm up to 1e100 over h^2 stay finite floats
        "bandwidth": (Options(("scott", "silverman")), Interval(numbers.Real, 1e-50, 1e150)),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, bandwidth="scott", threshold=0.95, contamination="auto"):
        self.bandwidth = bandwidth
        self.threshold = threshold
        self.contamination = contamination

    def _fit_model(self, X: np.ndarray) -> None:
        self.samples_ = X.copy()
        self.bandwidth_ = _bandwidth(self.bandwidth, X)

    def _log_density(self, X: np.ndarray, leave_one_out: bool = False) -> np.ndarray:
        S = self.samples_
        n, d = S.shape
        h2 = self.bandwidth_**2
        s_sq = np.einsum("ij,ij->i", S, S)
        out = np.empty(X.shape[0])
        step = max(1, _BLOCK // max(n, 1))
        for start in range(0, X.shape[0], step):
            block = X[start:start + step]
            sq = np.einsum("ij,ij->i", block, block)[:, None] - 2.0 * block @ S.T + s_sq
            np.maximum(sq, 0.0, out=sq)
            if leave_one_out:
                sq[np.arange(block.shape[0]), np.arange(start, start + block.shape[0])] = np.inf
            out[start:start + step] = logsumexp(-sq / (2.0 * h2), axis=1)
        m = n - 1 if leave_one_out else n
        return out - np.log(m) - 0.5 * d * np.log(2.0 * np.pi * h2)

    def log_density(self, X) -> np.ndarray:
        """log p(x) of each row (equation 1)."""
        self._check_fitted()
        return self._log_density(check_batch(X, self, self.n_features_in_))

    def _raw(self, X: np.ndarray) -> np.ndarray:
        return -self._log_density(X)

    def _reference_raw(self, X: np.ndarray) -> np.ndarray:
        if X.shape[0] < 2:
            return self._raw(X)
        return -self._log_density(X, leave_one_out=True)

    def _check_state(self) -> None:
        super()._check_state()
        check_array_state(self, "samples_", 2, shape=(None, self.n_features_in_))
        h = getattr(self, "bandwidth_", None)
        if isinstance(h, bool) or not isinstance(h, numbers.Real) or not np.isfinite(h) or h <= 0:
            raise StateError(f"ParzenDetector.bandwidth_ must be a positive number; got {h!r}.")
        if self.samples_.shape[0] == 0:
            raise StateError("ParzenDetector.samples_ is empty.")


def _bandwidth(rule, X: np.ndarray) -> float:
    """The bandwidth for ``rule`` (a name or a number) and the inputs ``X``."""
    if not isinstance(rule, str):
        return float(rule)
    n, d = X.shape
    var = X.var(axis=0, ddof=1) if n > 1 else np.zeros(d)
    sigma = float(np.sqrt(var.mean()))
    if not sigma > 0:
        sigma = 1.0
    factor = n ** (-1.0 / (d + 4))
    if rule == "silverman":
        factor *= (4.0 / (d + 2)) ** (1.0 / (d + 4))
    return sigma * factor
