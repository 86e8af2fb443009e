"""Kohonen & Oja's novelty filter: the part of an input outside the familiar subspace.

The filter is a linear map ``Phi`` (n_features x n_features). Its output

    x_tilde = Phi x                                                       (1)

is the *novelty* of ``x``: once trained, ``Phi`` is the orthogonal projector
onto the orthogonal complement of the subspace spanned by the familiar
inputs, so ``x_tilde`` is the component of ``x`` that no combination of
familiar inputs explains. The raw novelty is its length, ``||Phi x||``
(the vector itself is :meth:`KohonenNoveltyFilter.novelty_component`).

Two ways to learn ``Phi``:

- ``method="online"``: the orthogonalising rule of Kohonen & Oja (1976).
  Their network feeds its output back through lateral weights ``M``,
  ``x_tilde = x + M x_tilde``, adapted by the anti-Hebbian law
  ``dM/dt = -alpha x_tilde x_tilde^T``; with ``Phi = (I - M)^-1`` this is

      dPhi/dt = -alpha Phi x_tilde x_tilde^T Phi^T                        (2)

  (Kohonen 1989). The discrete step used here, one per input, starting from
  ``Phi = I``, is

      Phi <- Phi - (alpha / ||x||^2) x_tilde x_tilde^T                    (3)

  that is the Euler step of (2) where ``Phi`` is a projector (then
  ``Phi x_tilde = x_tilde``), with a step normalised by the input's energy
  as in the normalised LMS rule. For ``0 < alpha <= 1`` it keeps ``Phi``
  symmetric with eigenvalues in [0, 1], so ``||x_tilde|| <= ||x||``; along a
  direction that carries a share ``p`` of the inputs' energy the eigenvalue
  falls as about ``1 / (1 + alpha p t)`` after ``t`` inputs, and directions
  the inputs never visit keep eigenvalue 1. For inputs from a subspace it
  converges to ``I - P``, ``P`` the orthogonal projector onto the subspace.
  Learning continues online (``partial_fit``, ``learn_one``).
- ``method="pca"`` (batch): ``Phi = I - V_k^T V_k`` where the rows of ``V_k``
  are the first ``k`` right singular vectors of the training matrix X (the
  principal directions of the inputs' correlation matrix, uncentred like the
  filter itself), ``k = n_components``, or the fewest directions that hold
  a share ``n_components`` of the training energy ``sum(s_i^2)``.

The raw novelty is put on the comparable [0, 1] scale of
:mod:`novelty.baselines._calibration`. Model files hold ``filter_`` (and for
``pca`` the ``components_``): saving is supported.

References
----------
Kohonen, T. & Oja, E. (1976). Fast adaptive formation of orthogonalizing
filters and associative memory in recurrent networks of neuron-like
elements. Biological Cybernetics, 21, 85-95.

Kohonen, T. (1989). Self-Organization and Associative Memory, 3rd ed.
Springer (the novelty filter and equation (2)).

Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, section 1.3 (the filter as
the related work the habituating filter is compared with).
"""

from __future__ import annotations

import numbers

import numpy as np

from .._component import StateError, check_array_state, check_int_state
from .._validation import Interval, Options, check_batch
from ._calibration import CalibratedDetector

__all__ = ["KohonenNoveltyFilter"]


class KohonenNoveltyFilter(CalibratedDetector):
    """Kohonen & Oja's novelty filter: novelty outside the subspace of familiar inputs.

    Parameters
    ----------
    method : {"online", "pca"}, default="online"
        The orthogonalising rule (3), learning online, or the batch
        principal-subspace filter.
    n_components : int or float, default=0.95
        ``pca`` only: the number of familiar directions ``k``, or (a float in
        (0, 1)) the share of the training energy they must hold.
    learning_rate : float, default=0.5
        ``online`` only: alpha in (3), in (0, 1].
    n_epochs : int, default=1
        ``online`` only: passes over the data in :meth:`fit`.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    filter_ : ndarray of shape (n_features, n_features)
        Phi; the novelty component of ``x`` is ``filter_ @ x``.
    components_ : ndarray of shape (n_components, n_features)
        ``pca`` only: the familiar directions (orthonormal rows).
    n_components_ : int
        ``pca`` only: their number.
    reference_ : ndarray
        Calibration of the comparable scale (see ``_calibration``).
    n_features_in_ : int
        Number of features.

    References
    ----------
    Kohonen & Oja (1976); Kohonen (1989), the novelty filter.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> basis = np.linalg.qr(rng.normal(size=(16, 3)))[0].T      # a 3-D subspace of R^16
    >>> X = rng.normal(size=(300, 3)) @ basis
    >>> det = KohonenNoveltyFilter(method="pca", n_components=3).fit(X)
    >>> inside, outside = X[0], rng.normal(size=16)
    >>> bool(det.raw_novelty(inside[None])[0] < 1e-9), bool(det.raw_novelty(outside[None])[0] > 1)
    (True, True)
    """

    _parameter_rules = {
        "method": Options(("online", "pca")),
        "n_components": (
            Interval(numbers.Integral, 1, None),
            Interval(numbers.Real, 0, 1, closed="neither"),
        ),
        "learning_rate": Interval(numbers.Real, 0, 1, closed="right"),
        "n_epochs": Interval(numbers.Integral, 1, None),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, method="online", n_components=0.95, learning_rate=0.5, n_epochs=1, threshold=0.95,
                 contamination="auto"):
        self.method = method
        self.n_components = n_components
        self.learning_rate = learning_rate
        self.n_epochs = n_epochs
        self.threshold = threshold
        self.contamination = contamination

    @property
    def supports_online(self) -> bool:
        """Whether learning continues after ``fit`` (the online rule does)."""
        return self.method == "online"

    # ------------------------------------------------------------------ online
    def _start(self, X: np.ndarray) -> None:
        super()._start(X)
        self.filter_ = np.eye(X.shape[1])

    def _learn_one_raw(self, x: np.ndarray) -> float:
        phi = self.filter_
        novel = phi @ x
        raw = float(np.sqrt(novel @ novel))
        energy = float(x @ x)
        if energy > 0:
            phi -= np.outer(novel, novel) * (self.learning_rate / energy)
        return raw

    # ------------------------------------------------------------------- batch
    def _fit_model(self, X: np.ndarray) -> None:
        n_features = X.shape[1]
        _, s, vt = np.linalg.svd(X, full_matrices=False)
        energy = s**2
        total = energy.sum()
        rank = int(np.sum(s > s[0] * max(X.shape) * np.finfo(float).eps)) if s.size and total > 0 else 0
        if isinstance(self.n_components, numbers.Integral):
            k = min(int(self.n_components), rank)
        elif total > 0:
            k = int(np.searchsorted(np.cumsum(energy) / total, self.n_components) + 1)
            k = min(k, rank)
        else:
            k = 0
        self.components_ = vt[:k].copy()
        self.n_components_ = k
        self.filter_ = np.eye(n_features) - self.components_.T @ self.components_

    # ----------------------------------------------------------------- scoring
    def _raw(self, X: np.ndarray) -> np.ndarray:
        if self.method == "pca":
            # x - V^T V x is more accurate than (I - V^T V) x for inputs in the subspace
            novel = X - (X @ self.components_.T) @ self.components_
        else:
            novel = X @ self.filter_.T
        return np.sqrt(np.einsum("ij,ij->i", novel, novel))

    def novelty_component(self, X) -> np.ndarray:
        """The novelty vectors x_tilde = Phi x of each row (Kohonen's filter output)."""
        self._check_fitted()
        X = check_batch(X, self, self.n_features_in_)
        if self.method == "pca":
            return X - (X @ self.components_.T) @ self.components_
        return X @ self.filter_.T

    def _check_state(self) -> None:
        super()._check_state()
        d = self.n_features_in_
        check_array_state(self, "filter_", 2, shape=(d, d))
        if self.method == "pca":
            k = check_int_state(self, "n_components_")
            check_array_state(self, "components_", 2, shape=(k, d))
        elif not np.allclose(self.filter_, self.filter_.T, atol=1e-8):
            raise StateError("KohonenNoveltyFilter.filter_ must be symmetric.")
