"""The autoencoder novelty filter: reconstruction error of a small network.

Marsland et al. (2000, section 1.3) describe the Kohonen novelty filter in
its autoencoder form: a network trained (by back-propagation) to reproduce
its familiar inputs at its output through a narrow hidden layer, so that it
extracts their principal components; the difference between an input and
its reconstruction highlights what is novel in it (Japkowicz, Myers & Gluck
1995 use the same idea). Here the network is scikit-learn's
``MLPRegressor`` trained to map X to X; with hidden activations
``h_0 = x``, ``h_l = f(h_(l-1) W_l + b_l)`` and a linear output layer,

    x_hat = h_(L-1) W_L + b_L                                             (1)
    r(x) = ||x - x_hat||                                                  (2)

is the raw novelty, put on the comparable [0, 1] scale of
:mod:`novelty.baselines._calibration`.

Training is batch only (``supports_online = False``). Model files hold the
network's weights as one flat array (``parameters_``) with the layer sizes
(``layer_sizes_``), and equation (1) is evaluated here from them, so saving
is supported and no scikit-learn object is stored. Inputs should be scaled
(the paper's sonar readings lie in [0, 1]).

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, section 1.3.

Kohonen, T. (1993). Self-Organization and Associative Memory, 3rd ed. Springer.

Japkowicz, N., Myers, C. & Gluck, M. (1995). A novelty detection approach to
classification. Proc. IJCAI-95, 518-523.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from .._component import StateError, check_array_state, check_int_state
from .._validation import Instance, Interval, Options, check_batch
from ._calibration import CalibratedDetector

__all__ = ["AutoencoderFilter"]

_ACTIVATIONS = {
    "identity": lambda a: a,
    "logistic": lambda a: 1.0 / (1.0 + np.exp(-a)),
    "tanh": np.tanh,
    "relu": lambda a: np.maximum(a, 0.0),
}


class AutoencoderFilter(CalibratedDetector):
    """Autoencoder novelty filter: reconstruction error of a small MLP trained on familiar inputs.

    Parameters
    ----------
    hidden_layer_sizes : tuple of int or None, default=None
        Hidden layers; None is one bottleneck layer of
        ``max(1, n_features // 2)`` units.
    activation : {"tanh", "logistic", "relu", "identity"}, default="tanh"
        Activation of the hidden layers.
    solver : {"lbfgs", "adam", "sgd"}, default="lbfgs"
        scikit-learn's optimiser (L-BFGS suits the small data sets here).
    alpha : float, default=1e-4
        L2 penalty of the weights.
    max_iter : int, default=500
        Optimiser iterations.
    random_state : int or None, default=0
        Seed of the weight initialisation.
    threshold : float, default=0.95
        Novelty (comparable scale) above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.

    Attributes
    ----------
    layer_sizes_ : list of int
        Units per layer, input and output included.
    parameters_ : ndarray of shape (n_parameters,)
        Weights and biases of every layer, flattened in order (W_1, b_1, W_2, ...).
    n_iter_ : int
        Optimiser iterations run.
    reference_ : ndarray
        Calibration of the comparable scale.

    References
    ----------
    Marsland et al. (2000), section 1.3; Kohonen (1993); Japkowicz et al. (1995).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> t = rng.random((200, 1))
    >>> X = np.hstack([t, 1 - t, 0.5 * t, 0.2 + 0.0 * t])       # a 1-D curve in R^4
    >>> det = AutoencoderFilter(hidden_layer_sizes=(2,)).fit(X)
    >>> det.layer_sizes_
    [4, 2, 4]
    >>> bool(det.raw_novelty([[0.9, 0.9, 0.0, 0.9]])[0] > 10 * det.raw_novelty(X).mean())
    True
    """

    _parameter_rules = {
        "hidden_layer_sizes": Instance((tuple, list, type(None)), "a tuple of positive ints or None"),
        "activation": Options(tuple(_ACTIVATIONS)),
        "solver": Options(("lbfgs", "adam", "sgd")),
        "alpha": Interval(numbers.Real, 0, None),
        "max_iter": Interval(numbers.Integral, 1, None),
        "random_state": Interval(numbers.Integral, 0, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, hidden_layer_sizes=None, activation="tanh", solver="lbfgs", alpha=1e-4, max_iter=500,
                 random_state=0, threshold=0.95, contamination="auto"):
        self.hidden_layer_sizes = hidden_layer_sizes
        self.activation = activation
        self.solver = solver
        self.alpha = alpha
        self.max_iter = max_iter
        self.random_state = random_state
        self.threshold = threshold
        self.contamination = contamination

    def _validate_params(self) -> None:
        super()._validate_params()
        sizes = self.hidden_layer_sizes
        if sizes is not None and not (
            len(sizes) > 0 and all(isinstance(s, numbers.Integral) and not isinstance(s, bool) and s >= 1
                                   for s in sizes)
        ):
            raise ValueError(
                "The 'hidden_layer_sizes' parameter of AutoencoderFilter must be a non-empty tuple of "
                f"ints >= 1 or None. Got {sizes!r} instead."
            )

    def _fit_model(self, X: np.ndarray) -> None:
        # deferred: sklearn.neural_network is slow to import, needed only to fit
        from sklearn.neural_network import MLPRegressor

        hidden = self.hidden_layer_sizes
        if hidden is None:
            hidden = (max(1, X.shape[1] // 2),)
        net = MLPRegressor(hidden_layer_sizes=tuple(int(h) for h in hidden), activation=self.activation,
                           solver=self.solver, alpha=self.alpha, max_iter=self.max_iter,
                           random_state=self.random_state)
        with warnings.catch_warnings():
            # An autoencoder that has not fully converged is still a usable filter.
            warnings.simplefilter("ignore", ConvergenceWarning)
            net.fit(X, X)
        self.n_iter_ = int(net.n_iter_)
        self.layer_sizes_ = [X.shape[1], *[int(h) for h in hidden], X.shape[1]]
        self.parameters_ = np.concatenate([p.ravel() for W, b in zip(net.coefs_, net.intercepts_)
                                           for p in (W, b)])
        self._rebuild_scratch()

    def _rebuild_scratch(self) -> None:
        super()._rebuild_scratch()
        if not hasattr(self, "parameters_"):
            return
        layers, at = [], 0
        for n_in, n_out in zip(self.layer_sizes_[:-1], self.layer_sizes_[1:]):
            W = self.parameters_[at:at + n_in * n_out].reshape(n_in, n_out)
            at += n_in * n_out
            b = self.parameters_[at:at + n_out]
            at += n_out
            layers.append((W, b))
        self._layers = layers

    def reconstruct(self, X) -> np.ndarray:
        """The network's reconstruction x_hat of each row (equation 1)."""
        self._check_fitted()
        return self._reconstruct(check_batch(X, self, self.n_features_in_))

    def _reconstruct(self, X: np.ndarray) -> np.ndarray:
        f = _ACTIVATIONS[self.activation]
        h = X
        for i, (W, b) in enumerate(self._layers):
            h = h @ W + b
            if i < len(self._layers) - 1:
                h = f(h)
        return h

    def _raw(self, X: np.ndarray) -> np.ndarray:
        diff = X - self._reconstruct(X)
        return np.sqrt(np.einsum("ij,ij->i", diff, diff))

    def _check_state(self) -> None:
        super()._check_state()
        check_int_state(self, "n_iter_")
        sizes = getattr(self, "layer_sizes_", None)
        if not (isinstance(sizes, list) and len(sizes) >= 3
                and all(isinstance(s, int) and not isinstance(s, bool) and s >= 1 for s in sizes)
                and sizes[0] == sizes[-1] == self.n_features_in_):
            raise StateError(f"AutoencoderFilter.layer_sizes_ is not a valid list of layer sizes: {sizes!r}.")
        n = sum(a * b + b for a, b in zip(sizes[:-1], sizes[1:]))
        check_array_state(self, "parameters_", 1, shape=(n,))
