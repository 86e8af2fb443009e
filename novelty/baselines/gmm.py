"""A Gaussian mixture density of the familiar inputs; novelty = negative log-likelihood.

The density of familiar inputs is modelled as

    p(x) = sum_k w_k N(x; mu_k, Sigma_k)                                  (1)

fitted by expectation-maximisation (scikit-learn's ``GaussianMixture``), and
the raw novelty of ``x`` is ``-log p(x)`` (Bishop 1994: novelty as a low
density under the model of normal data). When ``n_components`` is None the
number of components K is the one of least Bayesian information criterion

    BIC(K) = -2 log L + n_parameters(K) log n                            (2)

over K = 1 .. ``max_components`` (Schwarz 1978).

Model files hold the fitted parameters as arrays (``weights_``, ``means_``,
``covariances_``); the log-likelihood is computed from them here, with the
Cholesky factor of each covariance,

    log N(x; mu, Sigma) = -d/2 log(2 pi) - sum_i log L_ii - ||L^-1 (x - mu)||^2 / 2,
    Sigma = L L^T,                                                        (3)

so saving is supported and no scikit-learn object is stored. The raw score
is put on the comparable [0, 1] scale of :mod:`novelty.baselines._calibration`.

References
----------
Bishop, C. M. (1994). Novelty detection and neural network validation. IEE
Proceedings - Vision, Image and Signal Processing, 141(4), 217-222.

Schwarz, G. (1978). Estimating the dimension of a model. Annals of
Statistics, 6(2), 461-464.

Dempster, A. P., Laird, N. M. & Rubin, D. B. (1977). Maximum likelihood from
incomplete data via the EM algorithm. JRSS B, 39(1), 1-38.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np
from scipy.linalg import solve_triangular
from scipy.special import logsumexp
from sklearn.exceptions import ConvergenceWarning

from .._component import StateError, check_array_state, check_int_state
from .._validation import Interval, Options, check_batch
from ._calibration import CalibratedDetector

__all__ = ["GaussianMixtureDetector"]


class GaussianMixtureDetector(CalibratedDetector):
    """Gaussian mixture model: novelty = negative log-likelihood, K chosen by BIC.

    Parameters
    ----------
    n_components : int or None, default=None
        Number of components K; None chooses it by BIC (equation 2).
    max_components : int, default=10
        Largest K tried when ``n_components`` is None (never more than the
        number of samples).
    covariance_type : {"full", "tied", "diag", "spherical"}, default="full"
        Form of the covariances, as in scikit-learn.
    reg_covar : float, default=1e-6
        Added to the covariances' diagonal.
    max_iter : int, default=100
        EM iterations.
    n_init : int, default=1
        EM restarts (the best is kept).
    random_state : int or None, default=0
        Seed of the EM initialisation.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    n_components_ : int
        The number of components used.
    weights_ : ndarray of shape (n_components,)
    means_ : ndarray of shape (n_components, n_features)
    covariances_ : ndarray of shape (n_components, n_features, n_features)
        Full covariance of each component, whatever ``covariance_type``.
    bic_ : ndarray of shape (n_tried,)
        BIC of each K tried (K = 1, 2, ...); only K itself when given.
    n_iter_ : int
        EM iterations of the chosen fit.
    reference_ : ndarray
        Calibration of the comparable scale.

    References
    ----------
    Bishop (1994); Schwarz (1978); scikit-learn's GaussianMixture (EM).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> X = np.vstack([rng.normal(c, 0.1, size=(100, 2)) for c in (0.0, 3.0)])
    >>> det = GaussianMixtureDetector().fit(X)
    >>> det.n_components_
    2
    >>> bool(det.raw_novelty([[1.5, 1.5]])[0] > det.raw_novelty([[3.0, 3.0]])[0])
    True
    """

    _parameter_rules = {
        "n_components": Interval(numbers.Integral, 1, None, allow_none=True),
        "max_components": Interval(numbers.Integral, 1, None),
        "covariance_type": Options(("full", "tied", "diag", "spherical")),
        "reg_covar": Interval(numbers.Real, 0, None),
        "max_iter": Interval(numbers.Integral, 1, None),
        "n_init": Interval(numbers.Integral, 1, None),
        "random_state": Interval(numbers.Integral, 0, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, n_components=None, max_components=10, covariance_type="full", reg_covar=1e-6,
                 max_iter=100, n_init=1, random_state=0, threshold=0.95, contamination="auto"):
        self.n_components = n_components
        self.max_components = max_components
        self.covariance_type = covariance_type
        self.reg_covar = reg_covar
        self.max_iter = max_iter
        self.n_init = n_init
        self.random_state = random_state
        self.threshold = threshold
        self.contamination = contamination

    def _mixture(self, k: int):
        # deferred: sklearn.mixture is slow to import, needed only to fit
        from sklearn.mixture import GaussianMixture

        return GaussianMixture(n_components=k, covariance_type=self.covariance_type, reg_covar=self.reg_covar,
                               max_iter=self.max_iter, n_init=self.n_init, random_state=self.random_state)

    def _fit_model(self, X: np.ndarray) -> None:
        if self.n_components is not None:
            candidates = [int(self.n_components)]
        else:
            candidates = list(range(1, min(self.max_components, X.shape[0]) + 1))
        best, bics = None, []
        with warnings.catch_warnings():
            # Small K on clustered data converge slowly; only the chosen fit matters.
            warnings.simplefilter("ignore", ConvergenceWarning)
            for k in candidates:
                model = self._mixture(k).fit(X)
                bics.append(model.bic(X))
                if best is None or bics[-1] < best[0]:
                    best = (bics[-1], model)
        model = best[1]
        self.bic_ = np.asarray(bics)
        self.n_components_ = int(model.n_components)
        self.n_iter_ = int(model.n_iter_)
        self.weights_ = model.weights_.copy()
        self.means_ = model.means_.copy()
        self.covariances_ = _full_covariances(model.covariances_, self.covariance_type,
                                              self.n_components_, X.shape[1])
        self._rebuild_scratch()

    def _rebuild_scratch(self) -> None:
        super()._rebuild_scratch()
        if hasattr(self, "covariances_"):
            self._chol = np.linalg.cholesky(self.covariances_)
            self._log_det_half = np.log(np.diagonal(self._chol, axis1=1, axis2=2)).sum(axis=1)

    def log_likelihood(self, X) -> np.ndarray:
        """log p(x) of each row under the mixture (equations 1 and 3)."""
        self._check_fitted()
        return self._log_p(check_batch(X, self, self.n_features_in_))

    def _log_p(self, X: np.ndarray) -> np.ndarray:
        n, d = X.shape
        log_terms = np.empty((n, self.n_components_))
        for k in range(self.n_components_):
            z = solve_triangular(self._chol[k], (X - self.means_[k]).T, lower=True, check_finite=False)
            log_terms[:, k] = (np.log(self.weights_[k]) - 0.5 * d * np.log(2 * np.pi)
                               - self._log_det_half[k] - 0.5 * np.einsum("ij,ij->j", z, z))
        return logsumexp(log_terms, axis=1)

    def _raw(self, X: np.ndarray) -> np.ndarray:
        return -self._log_p(X)

    def _check_state(self) -> None:
        super()._check_state()
        k = check_int_state(self, "n_components_", low=1)
        check_int_state(self, "n_iter_")
        d = self.n_features_in_
        w = check_array_state(self, "weights_", 1, shape=(k,))
        check_array_state(self, "means_", 2, shape=(k, d))
        cov = check_array_state(self, "covariances_", 3, shape=(k, d, d))
        check_array_state(self, "bic_", 1)
        if np.any(w <= 0) or not np.isclose(w.sum(), 1.0):
            raise StateError("GaussianMixtureDetector.weights_ must be positive and sum to 1.")
        try:
            np.linalg.cholesky(cov)
        except np.linalg.LinAlgError:
            raise StateError("GaussianMixtureDetector.covariances_ must be positive definite.") from None


def _full_covariances(cov: np.ndarray, kind: str, k: int, d: int) -> np.ndarray:
    """scikit-learn's covariances of any ``covariance_type`` as (k, d, d) matrices."""
    if kind == "full":
        return cov.copy()
    if kind == "tied":
        return np.repeat(cov[None], k, axis=0)
    if kind == "diag":
        return np.stack([np.diag(c) for c in cov])
    return np.stack([np.eye(d) * c for c in cov])  # spherical
