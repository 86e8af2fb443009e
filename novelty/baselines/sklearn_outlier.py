"""Any scikit-learn outlier detector as a novelty detector of this project.

:class:`SklearnOutlierDetector` wraps an estimator that has ``fit`` and
``score_samples`` (higher = more normal, scikit-learn's convention) and turns
it round to this project's convention:

    r(x) = -estimator.score_samples(x)                                    (1)

(or ``-estimator.decision_function(x)`` for an estimator without
``score_samples``: scikit-learn's decision function is its score shifted by
a constant, so the ranking is the same)
put on the comparable [0, 1] scale of :mod:`novelty.baselines._calibration`
(the estimator's own ``contamination`` and ``offset_`` play no part; the
``threshold`` acts on the comparable scale).

Four are registered through it, each with the estimator's main parameters as
its own, so that they can be built by name and saved:

- ``isolation-forest``: :class:`IsolationForestDetector` (Liu, Ting & Zhou
  2008); r is the anomaly score 2^(-E[h(x)] / c(n)) in (0, 1];
- ``one-class-svm``: :class:`OneClassSVMDetector` (Schoelkopf et al. 2001);
  r is minus the SVM's decision value before its offset;
- ``lof``: :class:`LocalOutlierFactorDetector`, ``LocalOutlierFactor`` with
  ``novelty=True`` (Breunig et al. 2000); r is the local outlier factor. Its
  reference scores are the training inputs' own outlier factors (each
  computed without the input itself), not the biased in-sample scores;
- ``elliptic-envelope``: :class:`EllipticEnvelopeDetector` (Rousseeuw & Van
  Driessen 1999); r is the squared Mahalanobis distance to the robust
  (minimum covariance determinant) centre.

Model files: a forest or a support-vector machine is not a set of arrays this
project can evaluate itself, and pickle is never used. The registered
detectors therefore keep the training inputs (``samples_``), and loading a
model refits the estimator on them with the same parameters and the same
integer ``random_state``, which reproduces it exactly under the same
scikit-learn version (refitting is deterministic), and checks that the
refitted estimator gives the training scores the file holds. Saving needs an
integer ``random_state`` where there is one.

The refit is the one cost of a load that the file could choose, so it is
capped by the library (storing the fitted forest or support vectors instead
would mean evaluating scikit-learn's internals here, and following them from
version to version): at most :data:`MAX_REFIT_SAMPLES` training inputs and
:data:`MAX_REFIT_VALUES` values; for the isolation forest at most
:data:`MAX_REFIT_TREE_SAMPLES` trees x samples per tree (1000 trees of the
default 256), for the one-class SVM at most :data:`MAX_REFIT_KERNEL_WORK`
inputs^2 x features (its kernel matrix) and for the elliptic envelope at most
:data:`MAX_REFIT_COVARIANCE_WORK` inputs x features^2 (its covariances).
Each cap is a load of seconds on a small machine (docs/guide/performance.md). A model beyond the caps is refused by ``save`` (which reads
the file back as ``load`` does) and by ``load``, before anything is fitted;
fitting it is not limited. A :class:`SklearnOutlierDetector`
wrapping an arbitrary estimator instance cannot be saved (its parameter is
an object a model file cannot name); ``save`` says so. To make another
estimator saveable, subclass as the four below do and register the subclass.

The adapter and its four detectors share one module although it is long:
each subclass only declares an estimator's parameters and how to build it,
mostly documentation, and none of them reads without the adapter.

References
----------
Liu, F. T., Ting, K. M. & Zhou, Z.-H. (2008). Isolation forest. Proc. ICDM
2008, 413-422.

Schoelkopf, B., Platt, J. C., Shawe-Taylor, J., Smola, A. J. & Williamson,
R. C. (2001). Estimating the support of a high-dimensional distribution.
Neural Computation, 13(7), 1443-1471.

Breunig, M. M., Kriegel, H.-P., Ng, R. T. & Sander, J. (2000). LOF:
identifying density-based local outliers. Proc. SIGMOD 2000, 93-104.

Rousseeuw, P. J. & Van Driessen, K. (1999). A fast algorithm for the minimum
covariance determinant estimator. Technometrics, 41(3), 212-223.
"""

from __future__ import annotations

import numbers

import numpy as np
from sklearn.base import BaseEstimator, clone

from .._component import StateError, check_array_state
from .._validation import Instance, Interval, Options
from ._calibration import CalibratedDetector

#: the most training inputs a model file may make ``load`` refit on
MAX_REFIT_SAMPLES = 20_000
#: the most training values (inputs x features) a model file may make ``load`` refit on
MAX_REFIT_VALUES = 2**20
#: the most trees x samples per tree an isolation-forest file may make ``load`` grow
MAX_REFIT_TREE_SAMPLES = 1000 * 256
#: the most inputs^2 x features a one-class-svm file may make ``load`` refit on (8,192 inputs of 32)
MAX_REFIT_KERNEL_WORK = 2**31
#: the most inputs x features^2 an elliptic-envelope file may make ``load`` refit on (4,096 inputs of 16)
MAX_REFIT_COVARIANCE_WORK = 2**20

__all__ = [
    "MAX_REFIT_SAMPLES",
    "MAX_REFIT_VALUES",
    "MAX_REFIT_TREE_SAMPLES",
    "MAX_REFIT_KERNEL_WORK",
    "MAX_REFIT_COVARIANCE_WORK",
    "SklearnOutlierDetector",
    "IsolationForestDetector",
    "OneClassSVMDetector",
    "LocalOutlierFactorDetector",
    "EllipticEnvelopeDetector",
]


class SklearnOutlierDetector(CalibratedDetector):
    """A scikit-learn outlier detector as a novelty detector (novelty = -score_samples).

    Parameters
    ----------
    estimator : estimator instance
        Any estimator with ``fit(X)`` and ``score_samples(X)`` (higher = more
        normal), e.g. ``IsolationForest()``, ``LocalOutlierFactor(novelty=True)``.
        It is cloned in ``fit``; its parameters are reachable as
        ``estimator__<name>``.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    samples_ : ndarray of shape (n_samples, n_features)
        The training inputs (what a saved model is refitted on).
    reference_ : ndarray
        Calibration of the comparable scale.

    Examples
    --------
    >>> import numpy as np
    >>> from sklearn.linear_model import SGDOneClassSVM
    >>> X = np.random.default_rng(0).normal(size=(200, 3))
    >>> det = SklearnOutlierDetector(SGDOneClassSVM(random_state=0)).fit(X)
    >>> det.predict([[0.0, 0.0, 0.0]]).tolist()
    [1]
    """

    _parameter_rules = {
        "estimator": Instance((BaseEstimator,), "a scikit-learn estimator with fit and score_samples"),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, estimator=None, threshold=0.95, contamination="auto"):
        self.estimator = estimator
        self.threshold = threshold
        self.contamination = contamination

    def _validate_params(self) -> None:
        super()._validate_params()
        est = self._build_estimator()
        if not (hasattr(est, "fit") and (hasattr(est, "score_samples") or hasattr(est, "decision_function"))):
            raise ValueError(
                f"The 'estimator' parameter of {type(self).__name__} must have fit and score_samples or "
                f"decision_function (LocalOutlierFactor needs novelty=True). Got {est!r} instead."
            )

    def _build_estimator(self):
        """A fresh, unfitted estimator (subclasses build it from their own parameters)."""
        return clone(self.estimator)

    # ---------------------------------------------------------------- learning
    def _fit_model(self, X: np.ndarray) -> None:
        self._estimator = self._build_estimator().fit(X)
        self.samples_ = X.copy()

    def _raw(self, X: np.ndarray) -> np.ndarray:
        # scikit-learn's convention, higher = more normal: score_samples, or decision_function (its shift)
        score = getattr(self._estimator, "score_samples", None) or self._estimator.decision_function
        return -np.asarray(score(X), dtype=np.float64)

    def _rebuild_scratch(self) -> None:
        super()._rebuild_scratch()
        if hasattr(self, "samples_") and not hasattr(self, "_estimator"):
            self._estimator = self._build_estimator().fit(self.samples_)

    def _import_state(self, arrays, values, children) -> None:
        super()._import_state(arrays, values, children)
        self._check_refit()  # once every subclass has rebuilt its scratch

    def _check_refit(self) -> None:
        """The refitted estimator must give the training scores the file holds (which set ``threshold_``)."""
        if not hasattr(self, "decision_scores_"):
            return
        again = self._novelty(self.samples_)
        if again.shape != self.decision_scores_.shape or not np.allclose(again, self.decision_scores_,
                                                                         rtol=1e-9, atol=1e-12):
            raise StateError(
                f"{type(self).__name__}.decision_scores_ are not the novelty of samples_ under the refitted "
                "estimator (the file was edited, or written with another scikit-learn version)."
            )

    # ------------------------------------------------------------------- files
    def save(self, path) -> None:
        """Write the model (training inputs + parameters; loading refits). See the module notes."""
        if type(self) is SklearnOutlierDetector:
            raise StateError(
                f"A SklearnOutlierDetector wrapping {type(self.estimator).__name__} cannot be saved: a "
                "model file holds only arrays and registered components, never pickled objects. Use a "
                "registered detector (isolation-forest, one-class-svm, lof, elliptic-envelope) or "
                "register a subclass that builds the estimator from plain parameters."
            )
        if "random_state" in self.get_params(deep=False) and not isinstance(self.random_state, numbers.Integral):
            raise StateError(
                f"{type(self).__name__} can be saved only with an integer random_state "
                f"(got {self.random_state!r}): "
                "loading refits the estimator on the stored inputs and must draw the same numbers."
            )
        super().save(path)

    def _check_state(self) -> None:
        super()._check_state()
        X = check_array_state(self, "samples_", 2, shape=(None, self.n_features_in_))
        if X.shape[0] == 0:
            raise StateError(f"{type(self).__name__}.samples_ is empty.")
        if X.shape[0] > MAX_REFIT_SAMPLES or X.size > MAX_REFIT_VALUES:
            raise StateError(
                f"{type(self).__name__} keeps {X.shape[0]} training inputs of {X.shape[1]} features, which "
                f"loading would refit on; a model file holds at most {MAX_REFIT_SAMPLES} inputs and "
                f"{MAX_REFIT_VALUES} values, so that reading it costs seconds (fit on fewer to save it)."
            )

    def _check_refit_work(self, work: int, cap: int, what: str) -> None:
        if work > cap:
            n, d = self.samples_.shape
            raise StateError(
                f"{type(self).__name__} keeps {n} training inputs of {d} features, which loading would "
                f"refit on: {work} {what}; a model file holds at most {cap}, so that reading it costs "
                "seconds (fit on fewer to save it)."
            )


class IsolationForestDetector(SklearnOutlierDetector):
    """Isolation forest (Liu, Ting & Zhou 2008) through the scikit-learn adapter.

    Parameters
    ----------
    n_estimators : int, default=100
    max_samples : "auto", int or float, default="auto"
    max_features : int or float, default=1.0
    bootstrap : bool, default=False
    random_state : int or None, default=0
        Must be an int for the model to be saved.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    The parameters are those of ``sklearn.ensemble.IsolationForest``.
    """

    _parameter_rules = {
        "n_estimators": Interval(numbers.Integral, 1, 2**31 - 1),
        "max_samples": (Options(("auto",)), Interval(numbers.Integral, 1, None),
                        Interval(numbers.Real, 0, 1, closed="right")),
        "max_features": (Interval(numbers.Integral, 1, None), Interval(numbers.Real, 0, 1, closed="right")),
        "bootstrap": Options((False, True)),
        "random_state": Interval(numbers.Integral, 0, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, n_estimators=100, max_samples="auto", max_features=1.0, bootstrap=False,
                 random_state=0, threshold=0.95, contamination="auto"):
        self.n_estimators = n_estimators
        self.max_samples = max_samples
        self.max_features = max_features
        self.bootstrap = bootstrap
        self.random_state = random_state
        self.threshold = threshold
        self.contamination = contamination

    def _check_state(self) -> None:
        super()._check_state()
        n = self.samples_.shape[0]
        if self.max_samples == "auto":
            per_tree = min(256, n)
        elif isinstance(self.max_samples, numbers.Integral):
            per_tree = min(int(self.max_samples), n)
        else:
            per_tree = int(self.max_samples * n)
        if self.n_estimators * per_tree > MAX_REFIT_TREE_SAMPLES:
            raise StateError(
                f"IsolationForestDetector grows {self.n_estimators} trees of {per_tree} samples, which loading "
                f"would grow again; a model file holds at most {MAX_REFIT_TREE_SAMPLES} trees x samples "
                "(1000 trees of the default 256), so that reading it costs seconds."
            )

    def _build_estimator(self):
        # deferred: sklearn.ensemble is slow to import, needed only by this detector
        from sklearn.ensemble import IsolationForest

        return IsolationForest(n_estimators=self.n_estimators, max_samples=self.max_samples,
                               max_features=self.max_features, bootstrap=self.bootstrap,
                               random_state=self.random_state)


class OneClassSVMDetector(SklearnOutlierDetector):
    """One-class support vector machine (Schoelkopf et al. 2001) through the scikit-learn adapter.

    Parameters
    ----------
    kernel : {"rbf", "linear", "poly", "sigmoid"}, default="rbf"
    gamma : {"scale", "auto"} or float, default="scale"
        The RBF kernel's width: scikit-learn's default ``"scale"``,
        ``1 / (n_features * X.var())``. PyOD's ``OCSVM`` (what ADBench
        reports as OCSVM) defaults to ``"auto"``, ``1 / n_features``: on data
        scaled to [0, 1] a kernel several times wider, a different model
        under the same name. ``gamma="auto"`` gives PyOD's.
    nu : float, default=0.5
    degree : int, default=3
    coef0 : float, default=0.0
    tol : float, default=1e-3
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    The parameters are those of ``sklearn.svm.OneClassSVM``, with its
    defaults; PyOD's ``OCSVM`` shares them but for ``gamma`` (above).
    """

    _parameter_rules = {
        "kernel": Options(("rbf", "linear", "poly", "sigmoid")),
        "gamma": (Options(("scale", "auto")), Interval(numbers.Real, 0, None, closed="neither")),
        "nu": Interval(numbers.Real, 0, 1, closed="right"),
        "degree": Interval(numbers.Integral, 0, 2**31 - 1),
        "coef0": Interval(numbers.Real, None, None),
        "tol": Interval(numbers.Real, 0, None, closed="neither"),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, kernel="rbf", gamma="scale", nu=0.5, degree=3, coef0=0.0, tol=1e-3, threshold=0.95,
                 contamination="auto"):
        self.kernel = kernel
        self.gamma = gamma
        self.nu = nu
        self.degree = degree
        self.coef0 = coef0
        self.tol = tol
        self.threshold = threshold
        self.contamination = contamination

    def _check_state(self) -> None:
        super()._check_state()
        n, d = self.samples_.shape
        self._check_refit_work(n * n * d, MAX_REFIT_KERNEL_WORK, "inputs^2 x features")

    def _build_estimator(self):
        # deferred: sklearn.svm is slow to import, needed only by this detector
        from sklearn.svm import OneClassSVM

        return OneClassSVM(kernel=self.kernel, gamma=self.gamma, nu=self.nu, degree=self.degree,
                           coef0=self.coef0, tol=self.tol)


class LocalOutlierFactorDetector(SklearnOutlierDetector):
    """Local outlier factor (Breunig et al. 2000) through the scikit-learn adapter.

    The parameters are those of ``sklearn.neighbors.LocalOutlierFactor``,
    always with ``novelty=True``.

    Parameters
    ----------
    n_neighbors : int, default=20
        Neighbours k (at most the number of training inputs minus one).
    metric : str, default="minkowski"
    p : float, default=2
    leaf_size : int, default=30
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.
    """

    _parameter_rules = {
        "n_neighbors": Interval(numbers.Integral, 1, None),
        "metric": Instance((str,), "a metric name"),
        "p": Interval(numbers.Real, 1, None),
        "leaf_size": Interval(numbers.Integral, 1, None),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, n_neighbors=20, metric="minkowski", p=2, leaf_size=30, threshold=0.95,
                 contamination="auto"):
        self.n_neighbors = n_neighbors
        self.metric = metric
        self.p = p
        self.leaf_size = leaf_size
        self.threshold = threshold
        self.contamination = contamination

    def _build_estimator(self):
        # deferred: sklearn.neighbors is slow to import, needed only by this detector
        from sklearn.neighbors import LocalOutlierFactor

        return LocalOutlierFactor(n_neighbors=self.n_neighbors, metric=self.metric, p=self.p,
                                  leaf_size=self.leaf_size, novelty=True)

    def _fit_model(self, X: np.ndarray) -> None:
        if X.shape[0] < 2:
            raise ValueError(
                f"{type(self).__name__} needs at least 2 samples (each needs a neighbour); "
                f"got n_samples = {X.shape[0]}. With fewer than n_neighbors + 1 = {self.n_neighbors + 1}, "
                "n_neighbors is lowered to n_samples - 1."
            )
        super()._fit_model(X)

    def _reference_raw(self, X: np.ndarray) -> np.ndarray:
        # The training inputs' own factors exclude each input from its neighbours.
        return -np.asarray(self._estimator.negative_outlier_factor_, dtype=np.float64)


class EllipticEnvelopeDetector(SklearnOutlierDetector):
    """Robust Gaussian envelope (minimum covariance determinant) through the scikit-learn adapter.

    Parameters
    ----------
    support_fraction : float or None, default=None
    assume_centered : bool, default=False
    random_state : int or None, default=0
        Must be an int for the model to be saved.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    The parameters are those of ``sklearn.covariance.EllipticEnvelope``.
    """

    _parameter_rules = {
        "support_fraction": Interval(numbers.Real, 0, 1, closed="right", allow_none=True),
        "assume_centered": Options((False, True)),
        "random_state": Interval(numbers.Integral, 0, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, support_fraction=None, assume_centered=False, random_state=0, threshold=0.95,
                 contamination="auto"):
        self.support_fraction = support_fraction
        self.assume_centered = assume_centered
        self.random_state = random_state
        self.threshold = threshold
        self.contamination = contamination

    def _check_state(self) -> None:
        super()._check_state()
        n, d = self.samples_.shape
        self._check_refit_work(n * d * d, MAX_REFIT_COVARIANCE_WORK, "inputs x features^2")

    def _build_estimator(self):
        # deferred: sklearn.covariance is slow to import, needed only by this detector
        from sklearn.covariance import EllipticEnvelope

        return EllipticEnvelope(support_fraction=self.support_fraction, assume_centered=self.assume_centered,
                                random_state=self.random_state)
