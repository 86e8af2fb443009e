"""Any PyOD outlier detector, by name, as a novelty detector of this project.

PyOD (Zhao, Nasrullah & Li 2019) scores outliers with ``decision_function``,
higher = more abnormal, this project's sign already; :class:`PyODDetector`
builds the model named by ``model`` (``"ECOD"``, ``"IForest"``, ``"KNN"``,
``"COPOD"``, ... as PyOD spells its classes), takes its raw novelty as

    r(x) = model.decision_function(x)                                     (1)

and puts it on the comparable [0, 1] scale of
:mod:`novelty.baselines._calibration`, calibrated on ``model.decision_scores_``
(PyOD's scores of the training inputs, which for neighbour methods such as
KNN leave each input out of its own neighbours). PyOD's own
``contamination``, ``threshold_`` and ``labels_`` play no part; this
detector's ``contamination`` and ``threshold`` work as for every detector.

Like for like with PyOD (what ADBench reports): the model is built with
PyOD's own defaults, only the parameters given being set, and scores a batch
in one call, as PyOD does. Some PyOD models are transductive: ECOD and COPOD
re-estimate their distributions on the training data *and the batch scored*
(COF, SOD, ROD, LMDD and CD also depend on the batch; measured with PyOD
3.6), so a scan's novelty depends on the scans scored with it, in PyOD as
here, and ``score_one``
scores one scan alone. The differences from PyOD's defaults are the
adapter's own: ``random_state`` is 0 (PyOD's None draws a new model each
fit; the benchmark sets the cell's seed), and PyOD's ``contamination=0.1``
decides only PyOD's labels, not the scores. ``model`` may also be a PyOD
detector object (any subclass of ``pyod.models.base.BaseDetector``), used as
it is: each fit clones it with its parameters (such a detector cannot be
saved; name its class instead).

PyOD is an optional dependency (``pip install "novelty-habituation[pyod]"``), imported
when a model is first built. Model files keep the training inputs and refit
the model on loading, as for the scikit-learn adapter
(:mod:`novelty.baselines.sklearn_outlier`): exact for deterministic models
(ECOD, COPOD, KNN) and for seeded ones given an integer ``random_state``.

References
----------
Zhao, Y., Nasrullah, Z. & Li, Z. (2019). PyOD: a Python toolbox for scalable
outlier detection. Journal of Machine Learning Research, 20(96), 1-7.

Li, Z., Zhao, Y., Hu, X., Botta, N., Ionescu, C. & Chen, G. H. (2022). ECOD:
unsupervised outlier detection using empirical cumulative distribution
functions. IEEE Transactions on Knowledge and Data Engineering.
"""

from __future__ import annotations

import importlib
import inspect
import numbers
import re

import numpy as np

from sklearn.base import clone

from .._component import StateError
from .._validation import Instance, Interval
from ..registry import check_parameters
from ._calibration import CalibratedDetector
from .sklearn_outlier import SklearnOutlierDetector

__all__ = ["PyODDetector"]

# Parameters this adapter sets itself, never through model_params.
_OWN = {"contamination": "contamination", "random_state": "random_state"}


def _pyod_class(name: str) -> type:
    """The PyOD detector class called ``name`` (any letter case), imported on demand."""
    try:
        # optional dependency, imported only when a PyOD model is built
        from pyod.models.base import BaseDetector
    except ImportError:
        raise ImportError(
            "The 'pyod' detector needs PyOD, an optional dependency: "
            "pip install \"novelty-habituation[pyod]\" (or pip install pyod)."
        ) from None
    modules = {name.lower(), re.sub(r"(?<=[a-z])(?=[A-Z])", "_", name).lower()}
    for module_name in sorted(modules):
        try:
            module = importlib.import_module(f"pyod.models.{module_name}")
        except ImportError:
            continue
        for attr, value in vars(module).items():
            if (attr.lower() == name.lower() and inspect.isclass(value)
                    and issubclass(value, BaseDetector) and value is not BaseDetector):
                return value
    raise ValueError(
        f"The 'model' parameter of PyODDetector must name a PyOD detector class as PyOD spells it "
        f"(e.g. 'ECOD', 'IForest', 'KNN', 'COPOD', 'LOF', 'HBOS'). Got {name!r} instead."
    )


class PyODDetector(SklearnOutlierDetector):
    """A PyOD outlier detector, by name, as a novelty detector (novelty = decision_function).

    Parameters
    ----------
    model : str or PyOD detector, default="ECOD"
        The PyOD class, as PyOD spells it (``"ECOD"``, ``"IForest"``,
        ``"KNN"``, ``"COPOD"``, ...; letter case is ignored), or a PyOD
        detector object, cloned with its parameters at each fit.
    model_params : dict or None, default=None
        Parameters of the PyOD model (e.g. ``{"n_neighbors": 10}``);
        ``novelty.make("pyod", model="KNN", n_neighbors=10)`` routes them here.
    random_state : int or None, default=0
        Seed, passed to models that take one (an int, to save the model);
        None leaves a model object's own.
    threshold, contamination
        As for :class:`~novelty.baselines.SklearnOutlierDetector`, whose
        attributes (``samples_``, ``reference_``) this detector has too.

    Examples
    --------
    >>> import numpy as np
    >>> import novelty
    >>> X = np.random.default_rng(0).normal(size=(200, 3))
    >>> det = novelty.make("pyod", model="ECOD").fit(X)  # doctest: +SKIP
    >>> det.predict([[0.0, 0.0, 0.0], [6.0, 6.0, 6.0]]).tolist()  # doctest: +SKIP
    [1, -1]
    """

    requires = ("pyod",)

    _parameter_rules = {
        "model": Instance((str, object), "the name of a PyOD detector class or a PyOD detector"),
        "model_params": Instance((dict, type(None)), "a dict of the PyOD model's parameters or None"),
        "random_state": Interval(numbers.Integral, 0, None, allow_none=True),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, model="ECOD", model_params=None, random_state=0, threshold=0.95, contamination="auto"):
        self.model = model
        self.model_params = model_params
        self.random_state = random_state
        self.threshold = threshold
        self.contamination = contamination

    @classmethod
    def from_params(cls, model="ECOD", **params):
        """Build from a flat parameter set: the adapter's own, the rest to the PyOD model.

        >>> det = PyODDetector.from_params("KNN", n_neighbors=10, threshold=0.9)
        >>> det.model_params, det.threshold
        ({'n_neighbors': 10}, 0.9)
        """
        own = {k: params.pop(k) for k in list(params) if k in cls._get_param_names()}
        if params:
            own["model_params"] = {**(own.get("model_params") or {}), **params}
        return cls(model=model, **own)

    def set_params(self, **params):
        """Set parameters, a PyOD model's own also by its name as :func:`novelty.make` takes it.

        ``set_params(n_neighbors=5)`` sets ``model_params["n_neighbors"]``
        (the routing of :meth:`from_params`), so a grid over
        ``{"n_neighbors": [...]}`` searches the model; the names are checked
        against the PyOD class in ``fit``, as for :func:`novelty.make`.
        """
        own = self._get_param_names()
        flat = {key: params.pop(key) for key in list(params) if key not in own and "__" not in key}
        if flat:
            given = params.get("model_params", self.model_params)
            params["model_params"] = {**(given or {}), **flat}
        return super().set_params(**params)

    def _validate_params(self) -> None:
        CalibratedDetector._validate_params(self)  # the scikit-learn adapter's own check does not apply
        self._build_estimator()

    def _build_estimator(self):
        if not isinstance(self.model, str):
            return self._clone_model()
        cls = _pyod_class(self.model)
        given = dict(self.model_params or {})
        accepted = [p for p in inspect.signature(cls.__init__).parameters if p != "self"]
        for name, own in _OWN.items():
            if name in given:
                raise ValueError(
                    f"PyODDetector sets the model's {name!r} itself; use the detector's '{own}' parameter."
                )
        check_parameters(f"the PyOD model {cls.__name__}", given, [p for p in accepted if p not in _OWN])
        if "random_state" in accepted:
            given["random_state"] = self.random_state
        return cls(**given)

    def _clone_model(self):
        """A fresh copy of a PyOD detector object, its seed set where one is given."""
        try:
            from pyod.models.base import BaseDetector  # optional dependency, imported when a model is built
        except ImportError:
            raise ImportError("A PyOD detector object needs PyOD: pip install \"novelty-habituation[pyod]\".") from None
        if not isinstance(self.model, BaseDetector):
            raise ValueError(f"The 'model' parameter of PyODDetector must be a PyOD class name or a PyOD detector "
                             f"(a pyod.models.base.BaseDetector). Got {self.model!r} instead.")
        model = clone(self.model)
        if self.random_state is not None and "random_state" in model.get_params(deep=False):
            model.set_params(random_state=self.random_state)
        return model

    def save(self, path) -> None:
        """Write the model; one built from a PyOD detector object cannot be (a file names classes, never objects)."""
        if not isinstance(self.model, str):
            raise StateError(f"A PyODDetector of a {type(self.model).__name__} object cannot be saved: a model "
                             f"file holds arrays and names, never objects; use model={type(self.model).__name__!r}.")
        super().save(path)

    # ------------------------------------------------------------- scoring
    def _raw(self, X: np.ndarray) -> np.ndarray:
        return np.asarray(self._estimator.decision_function(X), dtype=np.float64)

    def _reference_raw(self, X: np.ndarray) -> np.ndarray:
        return np.asarray(self._estimator.decision_scores_, dtype=np.float64)
