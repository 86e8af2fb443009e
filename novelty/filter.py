"""The habituating novelty filter: a clusterer composed with a synapse bank.

Marsland, Nehmzow & Shapiro (2000), section 2: each input is presented to a
clustering network; every unit connects to an output neuron through a
habituating synapse; the efficacy of the winner's synapse is the novelty of
the input, taken before the input is learned.

:class:`HabituatingFilter` is the estimator: its parameters, ``fit``, the
learning and scoring hooks of :class:`~novelty.detector.NoveltyDetector`
(scikit-learn's, River's and PyOD's faces), and how the winner's efficacy and
distance make the novelty (``novelty_rule``). The arithmetic is its engine's
(:mod:`novelty._kernels`: the reference loop :func:`learn_stream` in numpy, or
the same compiled); routing short parameter names (:mod:`novelty._filter.routing`),
the parts' parameters after fitting (:mod:`novelty._filter.parts`), calibrating
the match scale (:mod:`novelty._filter.calibration`), the synapse's range of
efficacy (:mod:`novelty._filter.efficacy_range`) and the single-scan protocol
(:mod:`novelty._filter.single_scan`) have modules of their own.

One module although over 300 lines: the class is about 310 of them, the
estimator's one job (parameters, fit, learn and score, the novelty rules),
which a split would only scatter across files a reader must hold together.
``filter.py`` beside ``_filter/``: the estimator users import by this name
(``novelty.filter.HabituatingFilter``), its private parts in the folder.
"""

from __future__ import annotations

import numbers

import numpy as np

from ._component import StateError, check_array_state
from ._filter import calibration, efficacy_range, parts, routing, scan_range, single_scan
from ._filter.scan_range import ScanRangeWarning
from ._kernels.choice import engine_for
from ._kernels.interface import Engine
from ._kernels.reference import learn_stream
from ._kernels.state import check_state
from ._validation import Instance, Interval, Options, check_batch
from .clusterers.base import Clusterer
from .detector import NoveltyDetector
from .habituation.base import Synapse
from .maps.habituating_map import HabituatingMap
from .match_scale import ScaleCalibration, mismatch_novelty, product_novelty
from .registry import build, of_kind

__all__ = ["HabituatingFilter", "ScanRangeWarning", "learn_stream", "hsom"]

class HabituatingFilter(NoveltyDetector):
    """A novelty filter made of any clusterer and any habituating synapse.

    Parameters
    ----------
    clusterer : str or Clusterer, default="som"
        The clustering network, by registry name (with its defaults) or as an
        instance (cloned in ``fit``; its parameters are reachable as
        ``clusterer__<name>`` for ``set_params`` and grid searches).
    synapse : str or Synapse, default="stanley"
        The synapse model, by name or instance.
    threshold : float, default=0.5
        Novelty above which :meth:`predict` calls a scan novel.
    contamination : "auto" or float in (0, 0.5], default="auto"
        Expected fraction of outliers in the training data; a float sets
        ``threshold_`` from the scores of :meth:`fit` instead of ``threshold``.
    stimulus : float, default=1.0
        Stimulus S presented to the winning neighbourhood's synapses. The
        efficacy is the novelty, on [0, 1] as every detector's: a synapse
        that bounds its efficacy (``Synapse.efficacy_range``) must keep it
        there under S, so Stanley's synapse needs ``y0 <= 1`` and a fixed
        point ``y0 - S / alpha >= 0`` (``S <= alpha * y0``; beyond it the
        efficacy, a synaptic strength, would turn negative, which the model
        of Stanley 1976 does not describe). ``S = alpha * y0`` as written in
        Python is accepted, although the product may round a little past the
        fixed point (a range leaving [0, 1] by a few roundings is taken to
        stay in it).
    n_epochs : int, default=1
        Passes over the data in :meth:`fit` (the robot's repeated runs).
    random_state : int, numpy Generator or None, default=0
        Seed of the clusterer's initialisation.
    novelty_rule : {"efficacy", "mismatch", "product"}, default="efficacy"
        How the winner's efficacy ``y_s`` and its match distance
        ``d = ||x - w_s||`` make the novelty (:mod:`novelty.match_scale`).
        ``"efficacy"``: ``y_s`` alone (the paper). ``"mismatch"`` (ours),
        ``1 - (1 - y_s) exp(-d^2 / (2 sigma^2))``: low only for an input
        close to a habituated unit. ``"product"`` (ours),
        ``y_s (1 - exp(-d^2 / (2 sigma^2)))``: high only for an input both
        far from its winner and won by an unhabituated unit.
    match_scale : float, "scott" or None, default=None
        sigma, a distance, or how to calibrate it on the first
        ``calibration_scans`` scans learned (:mod:`novelty.match_scale`).
        None: the ``match_quantile`` quantile of each calibration scan's
        distance to its nearest distinct other; ``"scott"`` (ours): Scott's
        normal-reference bandwidth of the calibration scans (Scott 1992),
        a tighter match.
    match_quantile : float, default=0.9
        The quantile of the calibration with ``match_scale=None``.
    calibration_scans : int, default=200
        How many of the first scans learned calibrate sigma (when it is not
        given and the rule or the clusterer needs it), one at a time: each
        is scored with the scale of the scans before it, whatever the
        batches (:mod:`novelty._filter.calibration`).

    Attributes
    ----------
    clusterer_ : Clusterer
        The fitted network.
    synapse_ : Synapse
        The fitted synapse bank, one synapse per unit of ``clusterer_``.
    match_scale_ : float or None
        sigma in use: ``match_scale``, or calibrated (None until known, or
        when neither the rule nor the clusterer needs one).
    calibration_scans_ : ndarray of shape (n_scans, n_features)
        The scans collected to calibrate sigma (only while calibrating and
        after; at most ``calibration_scans``).
    n_features_in_ : int
        Number of features of the inputs.

    Notes
    -----
    Parameters of the parts set after fitting (``set_params(synapse__alpha=1.5)``,
    or a new ``clusterer``) take effect at the next :meth:`fit`: learning on is
    refused until then (or until they are set back), scoring reads the fitted
    state (:mod:`novelty._filter.parts`). The filter's own parameters
    (``stimulus``, ``threshold``, ``novelty_rule``, ...) apply from the next
    call. The arithmetic is its engine's (:mod:`novelty._kernels`): compiled
    or the numpy reference, with the same results; :attr:`compiled_` says which.
    The engine is the one writer of the fitted parts: setting an attribute on
    ``clusterer_`` or ``synapse_`` (``det.synapse_.alpha = 1.5``) raises
    :class:`novelty.FittedPartError`, and their learned arrays are
    read-only: set the parameter on the filter and fit again, or refit.

    References
    ----------
    Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
    of an environment using habituation. Proc. SAB 2000, section 2.

    Examples
    --------
    >>> import numpy as np
    >>> import novelty
    >>> det = novelty.make("hsom")
    >>> scan = np.full(16, 0.5)
    >>> [round(det.score_learn_one(scan), 4) for _ in range(4)]
    [1.0, 0.6997, 0.4941, 0.3533]
    """

    _parameter_rules = {
        "clusterer": Instance((str, Clusterer), "a clusterer name or a Clusterer instance"),
        "synapse": Instance((str, Synapse), "a synapse name or a Synapse instance"),
        "threshold": Interval(numbers.Real, None, None),
        "stimulus": Interval(numbers.Real, 0, None),
        "n_epochs": Interval(numbers.Integral, 1, None),
        "random_state": (Interval(numbers.Integral, 0, None, allow_none=True),
                         Instance((np.random.Generator,), "a numpy Generator")),
        "novelty_rule": Options(("efficacy", "mismatch", "product")),
        "match_scale": (Options(("scott",)), Interval(numbers.Real, 0, None, closed="neither", allow_none=True)),
        "match_quantile": Interval(numbers.Real, 0, 1),
        "calibration_scans": Interval(numbers.Integral, 2, None),
    }

    def __init__(self, clusterer="som", synapse="stanley", threshold=0.5, stimulus=1.0,
                 n_epochs=1, random_state=0, novelty_rule="efficacy", match_scale=None,
                 match_quantile=0.9, calibration_scans=200, contamination="auto"):
        self.clusterer = clusterer
        self.synapse = synapse
        self.threshold = threshold
        self.contamination = contamination
        self.stimulus = stimulus
        self.n_epochs = n_epochs
        self.random_state = random_state
        self.novelty_rule = novelty_rule
        self.match_scale = match_scale
        self.match_quantile = match_quantile
        self.calibration_scans = calibration_scans

    # ------------------------------------------------------------- parameters
    def _validate_params(self) -> None:
        super()._validate_params()
        efficacy_range.check_template(self)

    @classmethod
    def from_params(cls, clusterer="som", synapse="stanley", **params):
        """Build a filter from component names and one flat set of parameters.

        Each parameter goes to whichever of the filter, the clusterer or the
        synapse takes it; ``clusterer__name`` / ``synapse__name`` settle a name
        both components take (:mod:`novelty._filter.routing`). A clusterer of
        world cells (``"world-cells"``: several winners a scan) composes with
        the synapse in a :class:`~novelty.maps.habituating_map.HabituatingMap`,
        which this returns (its module says why).

        >>> det = HabituatingFilter.from_params("som", "stanley", n_rows=5, alpha=1.2)
        >>> det.clusterer.n_rows, det.synapse.alpha
        (5, 1.2)
        """
        if _several_winners(clusterer):  # a map's world cells: several winners a scan
            return HabituatingMap.from_params(clusterer, synapse, **params)
        own, built = routing.route(cls._get_param_names(), clusterer, synapse, params)
        return cls(clusterer=built["clusterer"], synapse=built["synapse"], **own)

    def set_params(self, **params):
        """Set parameters, a component's also by its short name as :func:`novelty.make` takes it.

        ``set_params(alpha=1.2)`` is ``set_params(synapse__alpha=1.2)`` when
        the filter has no ``alpha`` and exactly one of its components takes
        it (the routing of :meth:`from_params`), so a grid over ``{"alpha":
        [...]}`` searches the synapse. ``get_params`` still reports the full
        names only: ``clone`` rebuilds the filter from them, and no parameter
        is reported twice. Parameters of the parts set after fitting take
        effect at the next fit (see the class notes).
        """
        vars(self).pop("_engine", None)  # another engine is chosen on the next call
        parts_now = {part: params.get(part, getattr(self, part)) for part in routing.PARTS}
        super().set_params(**routing.full_names(type(self).__name__, self._get_param_names(), parts_now,
                                                params))
        parts.note(self)
        return self

    def _check_online(self) -> None:
        super()._check_online()
        parts.check_online(self)

    def _adopt(self, new: "HabituatingFilter") -> None:
        super()._adopt(new)
        vars(self)["_parts_changed"] = []  # a new model is built from the parameters in force
        scan_range.carry(self, new)

    # ------------------------------------------------------------------- hooks
    def _start(self, X: np.ndarray) -> None:
        clusterer = build("clusterer", self.clusterer)
        if not isinstance(clusterer, Clusterer):
            raise ValueError(f"{type(clusterer).__name__} gives several winners a scan (the world's cells): it "
                             "composes with a synapse in novelty.maps.HabituatingMap, which novelty.make("
                             "'habituating', clusterer=..., synapse=...) builds.")
        synapse = build("synapse", self.synapse)
        clusterer.initialize(X, self.random_state)
        synapse.initialize(clusterer.n_units_)
        self.clusterer_ = clusterer
        self.synapse_ = synapse
        needed = self.novelty_rule != "efficacy" or clusterer.uses_match_scale
        calibrated = self._calibration_rule() is not None
        self.match_scale_ = None if calibrated else float(self.match_scale)
        if needed and calibrated:
            self.calibration_scans_ = np.empty((0, X.shape[1]))
        elif hasattr(self, "calibration_scans_"):
            del self.calibration_scans_
        self._rebuild_scratch()
        if clusterer.uses_match_scale:
            clusterer.calibrate(self.match_scale_)
        scan_range.warn_once(self, X)

    def _rebuild_scratch(self) -> None:
        vars(self).pop("_engine", None)  # chosen on the first call that needs one
        if not hasattr(self, "match_scale_"):  # a model file written before the scale existed
            self.match_scale_ = None
        parts.record(self)
        scans = getattr(self, "calibration_scans_", None)
        self._calibration = None if scans is None else ScaleCalibration(
            scans, self.calibration_scans, self.match_quantile, self._calibration_rule())

    def _current_engine(self) -> Engine:
        """The engine of the fitted parts as they are now, kept in ``_engine`` (written here
        only, outside the change counting of :meth:`~novelty._component.Component.__setattr__`):
        the one held while it holds them, else another (:func:`novelty._kernels.choice.engine_for`)."""
        held = vars(self).get("_engine")
        engine = engine_for(held, self)
        if engine is not held:
            vars(self)["_engine"] = engine
        return engine

    def _calibration_rule(self) -> str | None:
        """The rule that calibrates sigma (:mod:`novelty.match_scale`), None when it is given."""
        if self.match_scale is None:
            return "quantile"
        return self.match_scale if isinstance(self.match_scale, str) else None

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        if X.shape[0] > 1:  # a batch; one scan at a time is checked at the start only (its hot path)
            scan_range.warn_once(self, X)
        if self._calibration is not None and not self._calibration.full:
            return calibration.learn_calibrating(self, X, dt)
        return self._combine(*self._learn_raw(X, dt))

    def _learn_raw(self, X: np.ndarray, dt: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """Learn the rows of ``X``: each row's efficacy novelty and, unless the rule is the
        efficacy alone, its squared distance to its winner."""
        distances = None if self.novelty_rule == "efficacy" else np.empty(X.shape[0])
        return self._current_engine().learn(X, dt, float(self.stimulus), distances), distances

    def _combine(self, efficacy: np.ndarray, distances: np.ndarray | None) -> np.ndarray:
        if self.novelty_rule == "efficacy":
            return efficacy
        rule = mismatch_novelty if self.novelty_rule == "mismatch" else product_novelty
        return rule(efficacy, distances, self.match_scale_)

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        return self._novelty_of(*self._current_engine().score(X))

    def _novelty_of(self, rows: np.ndarray, distances: np.ndarray, efficacy: np.ndarray) -> np.ndarray:
        """The novelty of scans from their winners' rows, squared distances and efficacies."""
        new = self.clusterer_.grows_for(rows, distances)
        if new is not None:
            efficacy = np.where(new, self.synapse_.fresh_efficacy, efficacy)
        return self._combine(efficacy, distances)

    def score_learn_one(self, x, t=None) -> float:
        if t is None and type(x) is np.ndarray:
            out = single_scan.learn_one(self, x)
            if out is not None:
                return out
        return super().score_learn_one(x, t)

    score_learn_one.__doc__ = NoveltyDetector.score_learn_one.__doc__

    def score_one(self, x) -> float:
        if type(x) is np.ndarray:
            out = single_scan.score_one(self, x)
            if out is not None:
                return out
        return super().score_one(x)

    score_one.__doc__ = NoveltyDetector.score_one.__doc__

    # -------------------------------------------------------------- the model
    @property
    def compiled_(self) -> str:
        """Which loop learns: ``"compiled"``, or ``"reference (<why>)"``.

        Every registered clusterer and synapse declares compiled steps; a
        plugin that does not (or a subclass that does not declare them again)
        learns by :func:`learn_stream`, with the same results, more slowly. A
        pair whose compiled loop is still compiling is ``"compiled"`` (the
        reference learns until it is ready, with the same results).
        """
        self._check_fitted()
        return self._current_engine().why

    def winners(self, X) -> tuple[np.ndarray, np.ndarray]:
        """The winning units of ``X`` and their squared distances (as ``match`` computes them),
        without learning.

        As :meth:`Clusterer.winners <novelty.clusterers.Clusterer.winners>` finds them, but each
        unit by its stable id (``clusterer_.unit_ids_``), which a growing network keeps while its
        rows move as units are removed.
        """
        self._check_fitted()
        rows, distances = self._current_engine().nearest(check_batch(X, self, self.n_features_in_))
        return self.clusterer_.unit_ids_[rows], distances

    def _first_novelty(self) -> float:
        # A first perception wins a unit whose synapse has not habituated: y0.
        return float(build("synapse", self.synapse).initialize(1).efficacy_[0])

    @property
    def resting_novelty(self) -> float:
        """The novelty of a fully familiar input (the output neuron's resting activity).

        A fully familiar input matches a fully habituated unit exactly
        (``d = 0``): the resting efficacy, which the ``"product"`` rule
        multiplies by a zero mismatch.
        """
        if self.novelty_rule == "product":
            return 0.0
        synapse = self.synapse_ if hasattr(self, "synapse_") else build("synapse", self.synapse)
        return synapse.resting_efficacy

    def _threshold_advice(self) -> str | None:
        # Measured on the Radish logs (learn the first half, score the familiar scans of the second):
        # both thresholds below flagged most familiar scans (kmeans-stanley 87-100 %).
        contamination = self.contamination
        if not isinstance(contamination, str):
            return (f"threshold_ is the {1 - contamination:g} quantile of the novelty of the training scans, "
                    "scored after the synapses habituated to those very scans: new scans of the same place "
                    f"score higher, and far more than {contamination:g} of them can lie above it.")
        if self.novelty_rule == "mismatch":
            return (f"threshold={self.threshold:g} meets a novelty whose mismatch term is measured in the "
                    "spread of the training scans (the match scale sigma): new scans of a familiar place lie "
                    "farther from every unit than the training scans did, and most can lie above it.")
        return None

    def _novelty_bounds(self) -> tuple[float, float] | None:
        low, high = self.synapse_.efficacy_range(float(self.stimulus))
        if not (np.isfinite(low) and np.isfinite(high)):
            return None  # a synapse that does not bound its efficacy
        # mismatch: 1 - (1 - y) e with e in (0, 1]; product: y (1 - e)
        return {"efficacy": (low, high), "mismatch": (low, 1.0), "product": (0.0, high)}[self.novelty_rule]

    _novelty_interval = (0.0, 1.0)

    def _finite(self, novelty: np.ndarray) -> np.ndarray:
        """``novelty`` if finite and within the range its synapse keeps, else :class:`StateError`.

        Learning cannot leave the range (:meth:`_novelty_bounds`); a novelty
        outside it comes from a state changed in place (an ``efficacy_``
        written to), which the checks of ``fit``, ``set_params`` and a model
        file never saw.
        """
        novelty = super()._finite(novelty)
        if novelty.size and (novelty.min() < 0.0 or novelty.max() > 1.0):
            bounds = self._novelty_bounds()
            slack = efficacy_range.ROUNDINGS * np.finfo(np.float64).eps
            if bounds is not None and (novelty.min() < bounds[0] - slack or novelty.max() > bounds[1] + slack):
                raise StateError(
                    f"{type(self).__name__} computed a novelty from {novelty.min():.6g} to {novelty.max():.6g}, "
                    f"outside the [{bounds[0]:.6g}, {bounds[1]:.6g}] its synapse keeps: its learned state is "
                    "damaged (an efficacy_ written in place?). Refit it.")
        return novelty

    def _check_state(self) -> None:
        check_state(self)  # what an engine reads: shapes first
        self.synapse_.check_efficacy(self.stimulus)  # before the scores are checked against its range
        super()._check_state()
        scale = getattr(self, "match_scale_", None)
        if scale is not None and (isinstance(scale, bool) or not isinstance(scale, numbers.Real)
                                  or not 0 < scale < np.inf):
            raise StateError(f"HabituatingFilter.match_scale_ must be None or a positive number; got {scale!r}.")
        if hasattr(self, "calibration_scans_"):
            check_array_state(self, "calibration_scans_", 2, shape=(None, self.n_features_in_))


def _several_winners(clusterer) -> bool:
    """Whether ``clusterer`` (a registered name or an instance) declares several winners a scan."""
    if isinstance(clusterer, str):
        if clusterer not in of_kind("clusterer"):
            return False
        cls = of_kind("clusterer").get(clusterer)
    else:
        cls = type(clusterer)
    return "several-winners" in getattr(cls, "__dict__", {}).get("_capabilities", ())


def hsom(**params) -> HabituatingFilter:
    """The paper's Habituating SOM: a 10 x 10 Kohonen map with Stanley synapses.

    Every default is the value of Marsland, Nehmzow & Shapiro (2000): map
    10 x 10, learning rate 0.25, neighbourhood radius 1 (the 8 grid
    neighbours), both constant; tau = 3.33 (winner) and 14.3 (neighbours),
    alpha = 1.05, y0 = 1, explicit Euler steps, no forgetting.
    Parameters are routed as in :meth:`HabituatingFilter.from_params`.
    """
    return HabituatingFilter.from_params(clusterer="som", synapse="stanley", **params)
