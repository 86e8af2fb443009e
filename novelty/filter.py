"""The habituating novelty filter: a clusterer composed with a synapse bank.

Marsland, Nehmzow & Shapiro (2000), section 2: each input is presented to a
clustering network; every unit connects to an output neuron through a
habituating synapse; the efficacy of the winner's synapse is the novelty of
the input. For each scan, in order:

1. the clusterer finds the winner (and the units that learn with it);
2. the novelty is the winner's efficacy *before* this scan is learned;
3. when learning, the winner's and neighbours' synapses habituate (stimulus
   S = 1) and the clusterer adapts, possibly adding or removing units, which
   the synapse bank follows.

With learning off (the paper's non-learning runs) the output is a pure
function of the state, computed for a whole batch at once.

The per-scan loop is :func:`learn_stream`, on plain arrays, in one place.

One module although it is long (about 40% of it documentation): one
estimator, its reference loop and the hooks that share its state (start,
calibrate the match scale, learn, score), which read best together.
"""

from __future__ import annotations

import difflib
import math
import numbers
import warnings
import weakref

import numpy as np

from . import _kernels
from ._component import Component, StateError, check_array_state
from ._validation import Instance, Interval, Options, check_batch
from .clusterers.base import Clusterer
from .distances import squared_distances
from .detector import NoveltyDetector, _lock_of
from .habituation.base import Synapse
from .match_scale import ScaleCalibration, mismatch_novelty, product_novelty
from .registry import InvalidParameterError, build, check_parameters, of_kind

__all__ = ["HabituatingFilter", "ScanRangeWarning", "learn_stream", "hsom"]


def learn_stream(clusterer: Clusterer, synapse: Synapse, X: np.ndarray, dt: np.ndarray,
                 stimulus: float = 1.0, distances: np.ndarray | None = None) -> np.ndarray:
    """Present the rows of ``X`` in order, learning; return each row's efficacy novelty.

    This is the reference implementation of the filter's learning loop: the
    readable version any faster kernel must reproduce. The novelty of a row
    is its winner's efficacy before the row is learned; a row the network
    gives a unit of its own (``Growth.new_winner``) has that new unit's
    (fresh) efficacy, and the new unit's synapse then fires for it.
    ``distances``, if given, receives each row's squared distance to its
    winner.
    """
    novelty = np.empty(X.shape[0])
    for i in range(X.shape[0]):
        x = X[i]
        match = clusterer.match(x)
        novelty[i] = synapse.efficacy_[match.winner]
        if distances is not None:
            distances[i] = match.distance
        # Habituate on the rows of this match before the network may renumber them.
        synapse.step(match.winner, match.neighbours, stimulus, dt[i])
        growth = clusterer.adapt(x, match)
        if growth.removed.size:
            synapse.shrink(growth.removed)
        if growth.added:
            synapse.grow(growth.added)
            if growth.new_winner:
                novelty[i] = synapse.efficacy_[-1]
                synapse.fire(synapse.n_units_ - 1, stimulus, dt[i])
    return novelty


#: the type of the scans the compiled single-scan call takes as they are
_FLOAT64 = np.dtype(np.float64)

#: the detectors already warned of their scans' range: once per detector object, kept out of
#: its state (a model file, a copy and a comparison of states do not see it)
_WARNED_OF_RANGE: "weakref.WeakSet[HabituatingFilter]" = weakref.WeakSet()


class ScanRangeWarning(UserWarning):
    """Scans far outside the range a detector's parameters assume.

    The range is the clusterer's
    :meth:`~novelty.clusterers.base.Clusterer.assumed_range`; silence it with
    ``warnings.filterwarnings("ignore", category=novelty.ScanRangeWarning)``.
    """


#: roundings (of a double's epsilon, on the unit interval) by which a synapse's range of
#: efficacy may leave [0, 1] and still be taken to stay in it: ``y0 - S / alpha`` with
#: ``S = fl(alpha * y0)`` is within two of 0 (a rounding in the product, one in the quotient)
_ROUNDINGS = 4


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
        ``d = ||x - w_s||`` make the novelty. ``"efficacy"``: ``y_s`` alone
        (the paper). ``"mismatch"`` (habituation x mismatch, our extension,
        see :mod:`novelty.match_scale`)::

            n(x) = 1 - (1 - y_s) * exp(-d^2 / (2 sigma^2))

        low for an input that is close to a habituated unit (either alone
        keeps it high). ``"product"`` (also ours)::

            n(x) = y_s * (1 - exp(-d^2 / (2 sigma^2)))

        high only for an input that is both far from its winner and won by
        an unhabituated unit (either alone makes it low): a recurring input
        becomes familiar as its unit habituates *or* as the network comes to
        match it.
    match_scale : float, "scott" or None, default=None
        sigma, a distance, or how to calibrate it on the first
        ``calibration_scans`` scans learned (below;
        :mod:`novelty.match_scale`). None: the ``match_quantile`` quantile
        of each calibration scan's distance to its nearest distinct other
        calibration scan. ``"scott"`` (ours): Scott's normal-reference
        bandwidth of the calibration scans (Scott 1992), with ``m`` scans in
        ``d`` dimensions and ``s_j^2`` the sample variance of coordinate
        ``j``::

            sigma = sqrt(mean_j s_j^2) * m^(-1/(d+4))

        the bandwidth of a Parzen window on those scans (``parzen``), a
        tighter match than the quantile.
    match_quantile : float, default=0.9
        The quantile of the calibration with ``match_scale=None``.
    calibration_scans : int, default=200
        How many of the first scans learned calibrate sigma (when it is not
        given and the rule or the clusterer needs it). The scans are taken
        one at a time, so the result does not depend on how they were
        batched: sigma is re-estimated after each of them and then fixed. A
        scan learned before two distinct scans were seen is scored by its
        efficacy alone, and a growing network that takes the scale
        (``GrowWhenRequired(activity_threshold="auto")``) adds no unit
        before then; a model that has learned fewer scans scores with the
        scale of those it has (a first batch of one scan: the efficacy).

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
    or a new ``clusterer``) take effect at the next :meth:`fit`: the fitted
    ``clusterer_`` and ``synapse_`` keep the values they learned with, and
    learning on (:meth:`stream`, :meth:`partial_fit`, :meth:`learn_one`) is
    refused until the model is refitted or the values are set back, so that
    no scan is learned under parameters other than those it reports. Scoring
    reads the fitted state. The filter's own parameters (``stimulus``,
    ``threshold``, ``novelty_rule``, ...) apply from the next call.

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

    def _validate_params(self) -> None:
        super()._validate_params()
        synapse = self.synapse if isinstance(self.synapse, Synapse) else build("synapse", self.synapse)
        synapse._validate_params()
        self._check_efficacy_range(synapse)

    def _check_efficacy_range(self, synapse: Synapse) -> None:
        low, high = synapse.efficacy_range(float(self.stimulus))
        # a bound that leaves [0, 1] by roundings only is kept: S written as alpha * y0 rounds
        # to either side of Stanley's fixed point (y0 - S / alpha = -1.1e-16 for alpha = 1.72,
        # y0 = 0.956: about 6 % of pairs), and an efficacy a few roundings below 0 is what the
        # model reaches at S = alpha * y0 anyway (and loads: the checks of a model file allow it)
        slack = _ROUNDINGS * np.finfo(np.float64).eps
        if (np.isfinite(low) and low < -slack) or (np.isfinite(high) and high > 1 + slack):
            raise ValueError(
                f"The synapse's efficacy is the novelty, on [0, 1]; {synapse!r} under the stimulus "
                f"S = {self.stimulus} ranges over [{low:.6g}, {high:.6g}], which leaves it. Keep y0 <= 1 and "
                f"S <= alpha * y0 (Stanley's fixed point y0 - S / alpha >= 0): a smaller stimulus, a larger "
                "alpha, or a smaller y0."
            )

    # ------------------------------------------------------------ construction
    @classmethod
    def from_params(cls, clusterer="som", synapse="stanley", **params):
        """Build a filter from component names and one flat set of parameters.

        Each parameter goes to whichever of the filter, the clusterer or the
        synapse takes it; ``clusterer__name`` / ``synapse__name`` settle a name
        both components take.

        >>> det = HabituatingFilter.from_params("som", "stanley", n_rows=5, alpha=1.2)
        >>> det.clusterer.n_rows, det.synapse.alpha
        (5, 1.2)
        """
        own_names = cls._get_param_names()
        own = {k: params.pop(k) for k in list(params) if k in own_names}
        parts = {"clusterer": clusterer, "synapse": synapse}
        routed: dict[str, dict] = {"clusterer": {}, "synapse": {}}
        valid = {part: _parameters_of(part, spec) for part, spec in parts.items()}
        for key, value in params.items():
            part, _, name = key.partition("__")
            if name and part in routed:
                check_parameters(f"{part} {parts[part]!r}", {name: value}, valid[part])
                routed[part][name] = value
                continue
            taker = _component_taking(key, valid)
            if taker is None:
                all_valid = own_names + [n for p in routed for n in valid[p]]
                check_parameters("the habituating filter", {key: value}, all_valid)
            routed[taker][key] = value
        built = {part: build(part, spec, **routed[part]) for part, spec in parts.items()}
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
        vars(self).pop("_engine", None)  # the compiled loop is built again on the next call
        own = self._get_param_names()
        short = [key for key in params if key not in own and "__" not in key]
        if not short:
            super().set_params(**params)
            self._note_changed_parts()
            return self
        # a component given in the same call is the one a short name goes to; a value that is
        # not a component yet (checked in fit, as every parameter) takes no short name
        parts = {part: params.get(part, getattr(self, part)) for part in ("clusterer", "synapse")}
        valid = {part: _parameters_of(part, spec, strict=False) for part, spec in parts.items()}
        full = {key: value for key, value in params.items() if key not in short}
        for key in short:
            value = params[key]
            try:
                taker = _component_taking(key, valid)
            except InvalidParameterError as exc:
                raise ValueError(str(exc)) from None
            if taker is None:
                raise ValueError(_unknown_parameter(type(self).__name__, key, own, valid))
            if isinstance(parts[taker], str):
                raise ValueError(f"'{key}' is a parameter of the {taker} {parts[taker]!r}, given by name; "
                                 f"set {taker}= to an instance (novelty.make builds one) to set it.")
            full[f"{taker}__{key}"] = value
        super().set_params(**full)
        self._note_changed_parts()
        return self

    # ------------------------------------------------ parameters after fitting
    def _note_changed_parts(self) -> None:
        if self._is_fitted():
            self._parts_changed = self._changed_parts()

    def _parts_counts(self) -> tuple:
        """How many times attributes were set on the parts, templates and fitted ones
        (:meth:`novelty._component.Component.__setattr__`)."""
        return (getattr(self.clusterer, "_changes", 0), getattr(self.synapse, "_changes", 0),
                self.clusterer_._changes, self.synapse_._changes)

    def _changed_parts(self) -> list[str]:
        """The parameters of the parts that differ from those the fitted parts learned with."""
        changed = []
        for part in ("clusterer", "synapse"):
            spec, fitted = getattr(self, part), getattr(self, f"{part}_")
            template = build(part, spec) if isinstance(spec, str) else spec
            if type(template) is not type(fitted):
                changed.append(part)
                continue
            ours, theirs = template.get_params(deep=False), fitted.get_params(deep=False)
            changed += [f"{part}__{k}" for k in ours if repr(ours[k]) != repr(theirs.get(k))]
        return changed

    def _check_online(self) -> None:
        """Refuse to learn on after a part's parameters changed (the class notes), noticing also
        those set directly on the parts since the last call: on ``clusterer`` or ``synapse`` as
        ``set_params`` notes them, on the fitted ``clusterer_`` or ``synapse_`` checked against
        their rules (and then used)."""
        super()._check_online()
        counts = self._parts_counts()
        seen = getattr(self, "_parts_seen", None)
        if counts != seen:
            if seen is None or counts[2:] != seen[2:]:
                self.clusterer_._validate_params()
                self.synapse_._validate_params()
                self._check_efficacy_range(self.synapse_)
            if seen is None or counts[:2] != seen[:2]:
                self._parts_changed = self._changed_parts()
        changed = getattr(self, "_parts_changed", None)
        if changed:
            self._validate_params()  # a value that is wrong anyway is named as such first
            raise ValueError(
                f"{', '.join(changed)} changed after fitting; the fitted clusterer_ and synapse_ keep the "
                "values they learned with, so learning on would mix the two. Refit (fit) to learn with the "
                "new values, or set them back."
            )
        if counts != seen:
            self._parts_seen = counts

    def _adopt(self, new: "HabituatingFilter") -> None:
        super()._adopt(new)
        self._parts_changed = []  # a new model is built from the parameters in force

    # ------------------------------------------------------------------- hooks
    def _start(self, X: np.ndarray) -> None:
        clusterer = build("clusterer", self.clusterer)
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
        self._warn_outside_assumed_range(X)

    def _adopt(self, new: "HabituatingFilter") -> None:
        super()._adopt(new)
        if new in _WARNED_OF_RANGE:  # fit learns in a copy: the detector was warned
            _WARNED_OF_RANGE.add(self)

    def _warn_outside_assumed_range(self, X: np.ndarray) -> None:
        """Warn, once, of scans far outside the range the clusterer's parameters assume.

        "Far": beyond the range by more than its width ([-1, 2] for [0, 1]).
        The paper's detector on standardised scans (StandardScaler) learns
        little and flags nothing, silently; this says why.
        """
        if self in _WARNED_OF_RANGE:
            return
        assumed = self.clusterer_.assumed_range()
        if assumed is None:
            return
        low, high = assumed
        width = high - low
        least, most = float(X.min()), float(X.max())
        if least >= low - width and most <= high + width:
            return
        _WARNED_OF_RANGE.add(self)
        warnings.warn(
            f"{type(self).__name__}: its clusterer {type(self.clusterer_).__name__} starts its units uniformly "
            f"in [{low:g}, {high:g}] (init='uniform'), the range its parameters assume (the paper's "
            f"preprocessed sonar readings); these scans lie far outside it (from {least:.3g} to {most:.3g}). "
            f"Scale them into [{low:g}, {high:g}] (MinMaxScaler; preprocess='paper' for ranges in metres), "
            "or set init_range to their range, or init='sample'.", ScanRangeWarning, stacklevel=2)

    def _rebuild_scratch(self) -> None:
        self._engine = None  # the compiled loop of the fitted pair: built when first asked for
        if not hasattr(self, "match_scale_"):  # a model file written before the scale existed
            self.match_scale_ = None
        self._parts_changed = self._changed_parts()  # a file saved after set_params
        self._parts_seen = self._parts_counts()
        scans = getattr(self, "calibration_scans_", None)
        self._calibration = None if scans is None else ScaleCalibration(
            scans, self.calibration_scans, self.match_quantile, self._calibration_rule())

    def _calibration_rule(self) -> str | None:
        """The rule that calibrates sigma (:mod:`novelty.match_scale`), None when it is given."""
        if self.match_scale is None:
            return "quantile"
        return self.match_scale if isinstance(self.match_scale, str) else None

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        if X.shape[0] > 1:  # a batch; one scan at a time is checked at the start only (its hot path)
            self._warn_outside_assumed_range(X)
        calibration = self._calibration
        if calibration is None or calibration.full:
            return self._learn_block(X, dt)
        # Calibrating: each scan is scored with the scale of the scans before it,
        # so that any batching gives the same numbers. A clusterer that learns by
        # the scale (GWR's "auto" radius) learns one scan at a time; any other
        # learns the block in one call, since its learning does not read the scale.
        at_once = not self.clusterer_.uses_match_scale
        n = X.shape[0]
        if at_once:
            efficacy, distances = self._learn_raw(X, dt)
        else:
            efficacy = np.empty(n)
            distances = None if self.novelty_rule == "efficacy" else np.empty(n)
        scales = []  # each calibrating scan's scale, combined at the end
        i = 0
        while i < n and not calibration.full:
            scales.append(self.match_scale_)
            if not at_once:
                e, d = self._learn_raw(X[i : i + 1], dt[i : i + 1])
                efficacy[i] = e[0]
                if distances is not None:
                    distances[i] = d[0]
            if calibration.add(X[i]):
                self.match_scale_ = calibration.scale
                if not at_once:
                    self.clusterer_.calibrate(self.match_scale_)
            i += 1
        self.calibration_scans_ = calibration.scans
        out = np.empty(n)
        out[:i] = self._combine_each(efficacy[:i], None if distances is None else distances[:i], scales)
        if i < n:
            out[i:] = (self._combine(efficacy[i:], distances[i:]) if at_once
                       else self._learn_block(X[i:], dt[i:]))
        return out

    def _combine_each(self, efficacy: np.ndarray, distances: np.ndarray | None, scales: list) -> np.ndarray:
        """:meth:`_combine` of scans each with its own scale (None: the efficacy alone), in one
        pass: the same operations on each element as one scan at a time."""
        if self.novelty_rule == "efficacy":
            return efficacy
        known = np.array([s is not None for s in scales], dtype=bool)
        sigma = np.array([1.0 if s is None else s for s in scales], dtype=np.float64)
        rule = mismatch_novelty if self.novelty_rule == "mismatch" else product_novelty
        return np.where(known, rule(efficacy, distances, sigma), efficacy)

    # The hooks below first ask the fitted pair's engine (novelty._kernels) for a
    # compiled kernel; a kernel gives the same results as the reference code
    # after it, which runs when there is none.
    def _kernel_engine(self):
        """The engine of the fitted pair (:func:`novelty._kernels.engine_for`), or None: built
        once, again when a part was replaced or the parameters set (``set_params``)."""
        engine = getattr(self, "_engine", None)
        if engine is None or engine.clusterer is not self.clusterer_ or engine.synapse is not self.synapse_:
            engine = self._engine = _kernels.engine_for(self.clusterer_, self.synapse_)
        return engine

    def score_learn_one(self, x, t=None) -> float:
        if t is None and type(x) is np.ndarray:
            out = self._learn_one_compiled(x)
            if out is not None:
                return out
        return super().score_learn_one(x, t)

    score_learn_one.__doc__ = NoveltyDetector.score_learn_one.__doc__

    def _learn_one_compiled(self, x: np.ndarray) -> float | None:
        """The novelty of the scan ``x``, learned by the engine in one compiled call that also
        checks it; None, with nothing learned, when the call cannot take this path (a scan the
        check refuses, timestamps, calibrating, the engine not built or compiled yet): the
        general path then checks and learns it, and says what is wrong with it."""
        engine = vars(self).get("_engine")
        if engine is None or x.ndim != 1 or x.dtype is not _FLOAT64:
            return None
        flags = x.flags
        if not (flags.c_contiguous and flags.writeable):
            return None
        with _lock_of(self):  # this filter's own lock (an engine adopted from a fit's clone has the clone's)
            if vars(self).get("_engine") is not engine:
                # another thread replaced the engine while this one waited for the lock: the
                # one read above no longer holds the state
                return None
            if not engine.confirmed():
                # something was set on the filter or a part: checked as the general path does
                self._check_online()
                if not (self._served_by(engine) and engine.current()):
                    return None
                engine.confirm(self, *self._templates())
            if not engine.learn_one(x, float(self.stimulus)):
                return None
            if self.novelty_rule == "efficacy":
                out = engine.novelty1.item()
            else:
                out = float(self._combine(engine.novelty1.copy(), engine.distance1.copy())[0])
            if not math.isfinite(out):
                self._finite(np.array([out]))
            return out

    def _templates(self) -> list:
        """The unfitted parts that are components (their parameters checked by
        :meth:`_check_online`), as :meth:`Engine.confirm <novelty._kernels.engine.Engine.confirm>`
        watches them; a part given by name has nothing to watch (replacing it is a change of the
        filter)."""
        return [p for p in (self.clusterer, self.synapse) if isinstance(p, Component)]

    def _served_by(self, engine) -> bool:
        """Whether the engine learns the next scan as the general path would: it is this
        filter's, of its fitted parts, and the scan needs no timestamp and no calibration."""
        calibration = self._calibration
        return (vars(self).get("_engine") is engine and engine.clusterer is self.clusterer_
                and engine.synapse is self.synapse_ and self.last_time_ is None
                and (calibration is None or calibration.full))

    def _learn_block(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        return self._combine(*self._learn_raw(X, dt))

    def _learn_raw(self, X: np.ndarray, dt: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """Learn the rows of ``X``: each row's efficacy novelty and, unless the rule is the
        efficacy alone, its squared distance to its winner."""
        distances = None if self.novelty_rule == "efficacy" else np.empty(X.shape[0])
        engine = self._kernel_engine()
        if engine is not None:
            efficacy = engine.run(learn_stream, X, dt, float(self.stimulus), distances)
        else:
            efficacy = learn_stream(self.clusterer_, self.synapse_, X, dt, float(self.stimulus),
                                    distances=distances)
        return efficacy, distances

    def _combine(self, efficacy: np.ndarray, distances: np.ndarray | None) -> np.ndarray:
        if self.novelty_rule == "efficacy":
            return efficacy
        rule = mismatch_novelty if self.novelty_rule == "mismatch" else product_novelty
        return rule(efficacy, distances, self.match_scale_)

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        rows = np.empty(X.shape[0], dtype=np.int64)
        distances = np.empty(X.shape[0])
        kernel = _kernels.scorer(self.clusterer_, self.synapse_)
        if kernel is not None:
            efficacy = kernel(self.clusterer_, self.synapse_, X, rows, distances)
        else:
            rows[:], _ = self.clusterer_.winners(X)
            # the winners' distances as match() computes them (winners() expands the square)
            distances[:] = squared_distances(X, self.clusterer_.weights_[rows])
            efficacy = self.synapse_.efficacy_[rows]
        return self._novelty_of(rows, distances, efficacy)

    def _novelty_of(self, rows: np.ndarray, distances: np.ndarray, efficacy: np.ndarray) -> np.ndarray:
        """The novelty of scans from their winners' rows, squared distances and efficacies."""
        new = self.clusterer_.grows_for(rows, distances)
        if new is not None:
            efficacy = np.where(new, self.synapse_.fresh_efficacy, efficacy)
        return self._combine(efficacy, distances)

    def _novelty_one(self, x: np.ndarray) -> float:
        return float(self._novelty(x[None, :])[0])

    def score_one(self, x) -> float:
        if type(x) is np.ndarray:
            out = self._score_one_compiled(x)
            if out is not None:
                return out
        return super().score_one(x)

    score_one.__doc__ = NoveltyDetector.score_one.__doc__

    def _score_one_compiled(self, x: np.ndarray) -> float | None:
        """The novelty of the scan ``x`` scored by the engine in one compiled call that also
        checks it; None when the call cannot take this path (a scan the check refuses, no
        engine or scoring kernel loaded yet, the state changed since the engine read it): the
        general path then checks and scores it, and says what is wrong with it."""
        engine = vars(self).get("_engine")
        if engine is None or not engine.nearest_unit or x.ndim != 1 or x.dtype is not _FLOAT64:
            return None
        flags = x.flags
        kernels = _kernels.scoring_kernels()
        if not (flags.c_contiguous and flags.writeable) or kernels is None:
            return None
        with _lock_of(self):  # this filter's own lock (an engine adopted from a fit's clone has the clone's)
            if vars(self).get("_engine") is not engine:
                return None
            # confirmed for learning since: then also as it scores (the same parts, unchanged)
            if not (engine.confirmed() or (engine.clusterer is self.clusterer_
                                           and engine.synapse is self.synapse_
                                           and engine.unchanged())):
                return None
            if not engine.score_one(kernels, x):
                return None
            efficacy, distance, row = engine.scored1.tolist()
            if self.novelty_rule == "efficacy" and type(self.clusterer_).grows_for is Clusterer.grows_for:
                out = efficacy
            else:
                out = float(self._novelty_of(np.array([int(row)]), np.array([distance]),
                                             np.array([efficacy]))[0])
            if not math.isfinite(out):
                self._finite(np.array([out]))
            return out

    @property
    def compiled_(self) -> str:
        """Which loop learns: ``"compiled"``, or ``"reference (<why>)"``.

        Every registered clusterer and synapse declares compiled steps; a
        plugin that does not (or a subclass that does not declare them again)
        learns by :func:`learn_stream`, with the same results, more slowly.
        """
        self._check_fitted()
        return _kernels.path(self.clusterer_, self.synapse_)

    def winners(self, X) -> tuple[np.ndarray, np.ndarray]:
        """The winning units of ``X`` and their squared distances, without learning.

        As :meth:`Clusterer.winners <novelty.clusterers.Clusterer.winners>` returns them, but each
        unit by its stable id (``clusterer_.unit_ids_``), which a growing network keeps while its
        rows move as units are removed.
        """
        self._check_fitted()
        rows, distances = self.clusterer_.winners(check_batch(X, self, self.n_features_in_))
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

    def _novelty_bounds(self) -> tuple[float, float] | None:
        low, high = self.synapse_.efficacy_range(float(self.stimulus))
        if not (np.isfinite(low) and np.isfinite(high)):
            return None  # a synapse that does not bound its efficacy
        # mismatch: 1 - (1 - y) e with e in (0, 1]; product: y (1 - e)
        return {"efficacy": (low, high), "mismatch": (low, 1.0), "product": (0.0, high)}[self.novelty_rule]

    def _check_state(self) -> None:
        self.synapse_.check_efficacy(self.stimulus)  # before the scores are checked against its range
        super()._check_state()
        if self.synapse_.n_units_ != self.clusterer_.n_units_:
            raise StateError(
                f"The synapse bank has {self.synapse_.n_units_} synapses but the clusterer "
                f"has {self.clusterer_.n_units_} units."
            )
        if self.clusterer_.weights_.shape[1] != self.n_features_in_:
            raise StateError("The clusterer's weights do not match n_features_in_.")
        scale = getattr(self, "match_scale_", None)
        if scale is not None and (isinstance(scale, bool) or not isinstance(scale, numbers.Real)
                                  or not 0 < scale < np.inf):
            raise StateError(f"HabituatingFilter.match_scale_ must be None or a positive number; got {scale!r}.")
        if hasattr(self, "calibration_scans_"):
            check_array_state(self, "calibration_scans_", 2, shape=(None, self.n_features_in_))


def _parameters_of(part: str, spec, strict: bool = True) -> list[str]:
    """The parameter names of a clusterer or synapse, given by its registered name or as an instance.

    Not ``strict``: anything else (an unknown name, a value that is no
    component) takes no parameter, rather than raising.
    """
    if isinstance(spec, str):
        if not strict and spec not in of_kind(part):
            return []
        return of_kind(part).parameters(spec) or []
    if not strict and not hasattr(spec, "get_params"):
        return []
    return list(spec.get_params(deep=False))


def _component_taking(key: str, valid: dict[str, list[str]]) -> str | None:
    """Which component (``"clusterer"`` or ``"synapse"``) takes the short name ``key``; None if neither."""
    takers = [part for part in valid if key in valid[part]]
    if len(takers) > 1:
        raise InvalidParameterError(
            f"Parameter '{key}' is taken by both the clusterer and the synapse; "
            f"write clusterer__{key} or synapse__{key}."
        )
    return takers[0] if takers else None


def _unknown_parameter(owner: str, key: str, own: list[str], valid: dict[str, list[str]]) -> str:
    """The message for a name neither the filter nor a component takes: the full names listed."""
    short = {name: f"{part}__{name}" for part, names in valid.items() for name in names}
    close = difflib.get_close_matches(key, own + list(short), n=1)
    hint = ""
    if close:
        hint = f" (did you mean '{close[0]}'" + (f", that is '{short[close[0]]}'" if close[0] in short else "") + "?)"
    settable = sorted(own + list(short.values()))
    return f"Unknown parameter '{key}'{hint} for {owner}. Valid parameters: {', '.join(settable)}."


def hsom(**params) -> HabituatingFilter:
    """The paper's Habituating SOM: a 10 x 10 Kohonen map with Stanley synapses.

    Every default is the value of Marsland, Nehmzow & Shapiro (2000): map
    10 x 10, learning rate 0.25, neighbourhood radius 1 (the 8 grid
    neighbours), both constant; tau = 3.33 (winner) and 14.3 (neighbours),
    alpha = 1.05, y0 = 1, explicit Euler steps, no forgetting.
    Parameters are routed as in :meth:`HabituatingFilter.from_params`.
    """
    return HabituatingFilter.from_params(clusterer="som", synapse="stanley", **params)
