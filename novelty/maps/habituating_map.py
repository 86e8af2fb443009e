"""A habituating map: the paper's filter with the world's grid cells as its units, several winners a scan (ours).

Marsland, Nehmzow & Shapiro (2000) compose a clusterer with a bank of
habituating synapses; the efficacy of the winner's synapse is the novelty.
:class:`HabituatingMap` composes the clusterer of world cells
(:class:`~novelty.maps.cells.WorldCells`, registered as ``world-cells``: every
cell a scan's echoes fall in wins) with any registered synapse (Stanley's, as
in the paper, by default; Wang & Hsu's long-term memory, Staddon & Higa's two
time scales, a plugin's), on the ``points`` input (:mod:`novelty.io.scans.points`).
Each winner is stimulated by the synapse's own step (``Synapse.step`` with
several winners; compiled, its ``advance``), and the scan's novelty is the
cells' readout of their efficacies (equations (1) and (2) of
:mod:`novelty.maps.cells`). ``novelty.make("habituating",
clusterer="world-cells", synapse="wang-hsu")`` builds one.

Why an estimator of its own beside :class:`~novelty.filter.HabituatingFilter`:
the filter and its engines assume one winner a scan. Its novelty is that
winner's efficacy, combined with the winner's distance by the novelty rules;
its compiled driver is ``match``, ``stimulate(winner, neighbours)``, ``adapt``;
its scoring is the nearest unit; its state is checked against ``weights_`` of
shape (units, features). A map's scan wins hundreds of cells, its novelty is a
readout over them, and its units have no prototype in the scan's space and no
distance. So the map keeps the filter's composition (a registered clusterer, a
registered synapse, the synapse's step and schedule, its checks) and its own
loop (:mod:`novelty.maps.map_engine`: numpy, the specification; and one compiled
loop per synapse).

Two presets: ``habituating-map`` (:func:`habituating_map`, the defaults of
:class:`~novelty.maps.cells.WorldCells` and Stanley's synapse) and
``map-explore`` (:func:`map_explore`, for a robot that explores); how they
were chosen is in ``studies/maps``.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of an
environment using habituation. Proc. SAB 2000.

Stanley, J. C. (1976). Computer simulation of a model of habituation. Nature,
261, 146-148.
"""

from __future__ import annotations

import numbers

import numpy as np

from .._component import Component, StateError, check_int_state, declares, engine_writes, held_by_engine
from .._filter import efficacy_range, routing
from .._kernels.compiling import disabled
from .._validation import Instance, Interval
from ..detector import NoveltyDetector
from ..habituation.base import Synapse
from ..registry import build
from .cells import WorldCells, _unpack, cell_pack
from .map_engine import choose, warn_full
from ..io.scans.points import MAX_COORDINATE, example_rows, split_points
from .scan_rays import MapRangeWarning
from .scan_rays import sector_width as _sector_width

__all__ = ["HabituatingMap", "MapRangeWarning", "habituating_map", "map_explore", "HABITUATING_MAP", "MAP_EXPLORE",
           "cell_keys", "sector_width", "MAX_COORDINATE"]


def cell_keys(points, cell_size: float) -> np.ndarray:
    """The packed index of cell (i, j) = floor((x, y) / c) of each point: ``(i + 2^30) 2^32 + j + 2^31``.

    Exact for ``|i| < 2^30`` and ``|j| < 2^31`` (coordinates within :data:`MAX_COORDINATE`
    at cells of 1 mm or more), and increasing with (i, j) in that order.

    >>> cell_keys([[0.1, 0.1], [0.5, -0.1]], 0.4).tolist() == [2**62 + 2**31, (2**30 + 1) * 2**32 + 2**31 - 1]
    True
    """
    ij = np.floor(np.asarray(points, dtype=np.float64).reshape(-1, 2) / cell_size)
    return cell_pack(ij[:, 0], ij[:, 1])


def sector_width(pose, ends) -> float:
    """The angle one sector of a scan stands for (rad): :func:`novelty.maps.scan_rays.sector_width` of
    ``pose`` (x, y, ...) and the end points ``ends`` (n, 2).

    >>> round(float(np.degrees(sector_width([0.0, 0.0], [[1.0, 0.0], [0.0, 1.0], [-2.0, 0.0], [0.0, -1.0]]))), 6)
    90.0
    """
    ends = np.asarray(ends, dtype=np.float64).reshape(-1, 2)
    return float(_sector_width(float(pose[0]), float(pose[1]), ends[:, 0].copy(), ends[:, 1].copy()))


#: the names the map took before it composed a synapse, and where each goes now
_RENAMED = {"tau": "tau_winner"}


def _settings(params: dict) -> dict:
    """``params`` in today's names: ``tau`` is the synapse's ``tau_winner``; ``tau_neighbour`` None (the
    eight cells around a hit cell held) is ``neighbours=False``, a number also ``neighbours=True``."""
    out = {_RENAMED.get(name, name): value for name, value in params.items()}
    if "tau_neighbour" in out and "neighbours" not in out:
        out["neighbours"] = out["tau_neighbour"] is not None
    if out.get("tau_neighbour", 0) is None:
        del out["tau_neighbour"]
    return out


class HabituatingMap(NoveltyDetector):
    """World cells composed with any synapse: the paper's filter on a map of the world (module docstring; ours).

    Parameters
    ----------
    clusterer : str or WorldCells, default="world-cells"
        The clusterer of world cells, by name (with its defaults) or as an
        instance (cloned in ``fit``): its parameters are the map's
        (:class:`~novelty.maps.cells.WorldCells`), reachable as
        ``clusterer__<name>`` or by their short names.
    synapse : str or Synapse, default="stanley"
        The synapse model, by name or instance, one per cell.
    stimulus : float, default=1.0
        The stimulus S each winner's synapse receives.
    n_epochs : int, default=1
        Passes over the data in :meth:`fit`.
    threshold : float, default=0.5
        Novelty above which :meth:`predict` says novel.
    contamination : "auto" or float in (0, 0.5], default="auto"

    Attributes
    ----------
    clusterer_ : WorldCells
        The fitted map: its tiles, passes, last hits, scans.
    synapse_ : Synapse
        The fitted synapse bank, one synapse per cell of ``clusterer_``.
    n_features_in_ : int

    Examples
    --------
    A corridor along x with walls at y = +-2 (two sectors, left and right, the
    ring's threshold 4 m), the robot at x = 0.1 and 1.1; then a box at y = 0.5
    where the left sector's ray had passed once (weight 1 - 1/e): its one novel
    cell among the ``top`` two gives 0.632 / 2 (cells never passed weighing
    nothing, each sector on its axis, each cell read alone):

    >>> corridor = lambda x, y_left, near_left: [x, 0.0, 0.0, near_left, 0.5, x, x, y_left, -2.0]
    >>> det = habituating_map(cell_size=0.5, free_scale=1.0, unseen=0.0, tolerance=0, arc=0.0)
    >>> det = det.fit([corridor(0.1, 2.0, 0.5), corridor(1.1, 2.0, 0.5)])
    >>> det.novelty([corridor(1.1, 2.0, 0.5), corridor(1.1, 0.5, 0.875)]).round(3).tolist()
    [0.0, 0.316]
    """

    #: the rows it reads: the ``points`` input (:mod:`novelty.io.scans.points`), not any rows
    input_layout = "points"

    _parameter_rules = {
        "clusterer": Instance((str, WorldCells), "a clusterer of world cells, by name or as a WorldCells"),
        "synapse": Instance((str, Synapse), "a synapse name or a Synapse instance"),
        "stimulus": Interval(numbers.Real, 0, None),
        "n_epochs": Interval(numbers.Integral, 1, None),
        "threshold": Interval(numbers.Real, None, None),
    }

    def __init__(self, clusterer="world-cells", synapse="stanley", stimulus=1.0, n_epochs=1, threshold=0.5,
                 contamination="auto"):
        self.clusterer = clusterer
        self.synapse = synapse
        self.stimulus = stimulus
        self.n_epochs = n_epochs
        self.threshold = threshold
        self.contamination = contamination

    @classmethod
    def from_params(cls, clusterer="world-cells", synapse="stanley", **params) -> "HabituatingMap":
        """A map from its parts' names and one flat set of parameters, each to the part that takes it.

        >>> det = HabituatingMap.from_params(synapse="wang-hsu", cell_size=0.2, beta=2.0)
        >>> det.clusterer.cell_size, type(det.synapse).__name__, det.synapse.beta
        (0.2, 'WangHsuSynapse', 2.0)
        """
        own, built = routing.route(cls._get_param_names(), clusterer, synapse, params)
        return cls(clusterer=built["clusterer"], synapse=built["synapse"], **own)

    def set_params(self, **params):
        """Set parameters, a part's also by its short name (``set_params(top=3)``: the clusterer's).

        A part's parameter set on a fitted map applies to its fitted part too, from the next call (how the
        map reads and learns: ``top``, ``tolerance``, ``alpha``, ...); a part replaced, from the next fit.
        """
        parts = {part: params.get(part, getattr(self, part)) for part in routing.PARTS}
        full = routing.full_names(type(self).__name__, self._get_param_names(), parts, params)
        super().set_params(**full)
        for key, value in full.items():
            part, _, name = key.partition("__")
            fitted = getattr(self, f"{part}_", None) if name and part in routing.PARTS else None
            if isinstance(fitted, Component):
                with engine_writes((fitted,)):  # the map's own write: its engine reads it again (_engine)
                    fitted.set_params(**{name: value})
        return self

    @classmethod
    def _example_rows(cls, seed: int = 0, n: int = 120) -> np.ndarray:
        """Rows of the points input for generic checks (:func:`novelty.io.scans.points.example_rows`)."""
        return example_rows(seed, n)

    def __getstate__(self):
        # the engine is scratch, made again from the parts (a compiled one holds modules, which do not pickle)
        return {k: v for k, v in vars(self).items() if k not in ("_map_engine", "_map_seen")}

    # ------------------------------------------------------------------ parameters
    def _validate_params(self) -> None:
        super()._validate_params()
        efficacy_range.check_template(self)

    def _parts(self) -> tuple[WorldCells, Synapse]:
        cells, synapse = build("clusterer", self.clusterer), build("synapse", self.synapse)
        if not declares(cells, "several-winners"):
            raise ValueError(f"HabituatingMap composes a clusterer of world cells ('world-cells'); got "
                             f"{type(cells).__name__}, one winner a scan: novelty.make('habituating', "
                             f"clusterer=...) composes that one.")
        return cells, synapse

    def _first_novelty(self) -> float:
        cells, synapse = self._parts()
        return cells.first_novelty(synapse.initialize(1).fresh_efficacy)

    def _novelty_bounds(self) -> tuple[float, float] | None:
        high = self.synapse_.efficacy_range(float(self.stimulus))[1]
        return (0.0, float(high)) if np.isfinite(high) else None

    # ------------------------------------------------------------------ learning and scoring
    def _start(self, X: np.ndarray) -> None:
        cells, synapse = self._parts()
        self.clusterer_ = cells.initialize(X)
        self.synapse_ = synapse.initialize(0)
        vars(self).pop("_map_engine", None)

    def _learn(self, X: np.ndarray, dt: np.ndarray) -> np.ndarray:
        costs = self._check_rows(X)
        with self._own_call():
            engine = self._engine()
            out = engine.learn(X, dt, float(self.stimulus), costs)
        self._seen()
        warn_full(self.clusterer_, engine.passed_by, stacklevel=5)
        engine.passed_by = 0
        return out

    def _novelty(self, X: np.ndarray) -> np.ndarray:
        costs = self._check_rows(X)
        with self._own_call():
            return self._engine().score(X, costs)

    def _own_call(self):
        """The block of one of the map's own calls on its fitted parts, which are read-only outside such
        blocks (:func:`novelty._component.held_by_engine`): its engine writes them, and the compiled kernels
        read them as writable arrays (numba types a read-only array as another type, compiled again)."""
        return engine_writes((self.clusterer_, self.synapse_))

    def _engine(self):
        """The engine of the parts as they are (:mod:`novelty.maps.map_engine`): the one held while nothing was set
        on the parts since it read them, else another, chosen once the state is checked."""
        engine = vars(self).get("_map_engine")
        pending = getattr(engine, "pending", None)
        if engine is not None and vars(self).get("_map_seen") == self._counts() and not (
                pending is not None and pending.ready):
            return engine
        self._check_parts()
        engine = vars(self)["_map_engine"] = choose(self.clusterer_, self.synapse_)
        for part in (self.clusterer_, self.synapse_):  # the engine is the one writer of what the map learned
            held_by_engine(part)
        self._seen()
        return engine

    def _counts(self) -> tuple:
        return (id(self.clusterer_), self.clusterer_._changes, id(self.synapse_), self.synapse_._changes, disabled())

    def _seen(self) -> None:
        vars(self)["_map_seen"] = self._counts()

    @property
    def compiled_(self) -> str:
        """Which loop learns: ``"compiled"``, or ``"reference (<why>)"`` (:mod:`novelty.maps.map_engine`)."""
        self._check_fitted()
        return self._engine().why

    def _check_rows(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Refuse rows with a scan that would touch more than ``max_scan_cells`` cells, before anything is
        learned; warn of sectors cut at ``max_range``. Returns at most how many cells each row touches and its
        cones' widths (what the engine makes room by and reads the rows with)."""
        from . import grid_kernels as grid  # numba: imported when a map first reads rows (a second, once)

        cells = self.clusterer_
        split_points(X, type(self).__name__, bounded=True)
        widths = np.empty(X.shape[0])
        sizes, _ = grid.check_costs(X, cells, -1.0 if isinstance(cells.arc, str) else float(cells.arc),
                                    float(cells.cell_size), widths=widths)
        return sizes, widths

    # ------------------------------------------------------------------ what a score is made of
    def explain(self, x) -> dict:
        """What makes one scan's novelty, cell by cell, against the map as it is (nothing is learned; an
        unfitted map is an empty one).

        Returns a dict: over the cells the scan's echoes fall in (sorted by (i, j)), ``cells`` (h, 2) their
        indices, ``centres`` (h, 2) their centres (m), ``efficacy`` as the map reads it (the least within
        ``tolerance``), ``own_efficacy`` the cell's own synapse's, ``passes`` (f), ``last_hit`` (the scan that
        last hit it, 0: never), ``novelty`` (v, equation (1) of :mod:`novelty.maps.cells`), ``scoring`` (among
        the ``top`` whose mean is the scan's novelty, v > 0) and ``seen`` (the map had evidence there: passed
        or hit before); ``passed`` (p, 2) the cells the scan's rays pass (each once, none hit); ``score`` the
        scan's novelty (equation (2): :meth:`novelty` gives the same) and ``seen_share`` (:meth:`seen_share`).

        >>> det = habituating_map(arc=0.0, tolerance=0).fit([[0.0, 0.0, 0.0, 0.5, 2.05, 0.05]] * 3)
        >>> out = det.explain([0.0, 0.0, 0.0, 0.5, 1.05, 0.05])   # an echo halfway, where the rays passed
        >>> out["cells"].tolist(), out["passes"].tolist(), out["seen"].tolist(), round(out["score"], 3)
        ([[10, 0]], [3.0], [True], 0.416)
        """
        x = np.asarray(x, dtype=np.float64).reshape(1, -1)
        if not self._is_fitted():   # the empty map a first scan meets
            self._validate_params()
            empty = self._unfitted_copy()
            empty._begin(x)
            return empty.explain(x[0])
        self._check_rows(np.ascontiguousarray(x))
        cells, synapse = self.clusterer_, self.synapse_
        with self._own_call():
            scan = cells.scan_cells(x[0])
            index = cells.index()
            fresh = synapse.fresh_efficacy
            v, score = cells.readout(scan.hits, index.units, synapse.efficacy_, fresh)
            block = cells.readout_efficacy(scan.hits, index.units, synapse.efficacy_, fresh)
            state = self.read_cells(scan.hits)
        k = v.size if cells.top is None else min(int(cells.top), v.size)
        scoring = np.zeros(v.size, dtype=bool)
        scoring[np.argsort(-v, kind="stable")[:k]] = True
        scoring &= v > 0
        seen = (state["passes"] > 0) | (state["last_hit"] > 0)
        passed = np.unique(cell_pack(scan.passed[:, 0], scan.passed[:, 1]))
        passed = np.setdiff1d(passed, cell_pack(scan.hits[:, 0], scan.hits[:, 1]))
        return {"cells": scan.hits, "centres": (scan.hits + 0.5) * float(cells.cell_size), "efficacy": block,
                "own_efficacy": state["efficacy"], "passes": state["passes"], "last_hit": state["last_hit"],
                "novelty": v, "scoring": scoring, "seen": seen, "score": score,
                "seen_share": _seen_share(v, scoring, seen), "passed": _unpack(passed)}

    def cell_novelty(self, x) -> tuple[np.ndarray, np.ndarray]:
        """The cells one scan hits, and each one's novelty ``v`` as the scan's novelty reads it (no learning).

        The centres and novelties of :meth:`explain`, for a live node's markers.

        Parameters
        ----------
        x : array-like of shape (n_features,)
            One row of the ``points`` input.

        Returns
        -------
        centres : ndarray of shape (n_hit, 2)
            The hit cells' centres in the world frame (m).
        novelty : ndarray of shape (n_hit,)
            Their ``v`` (equation (1) of :mod:`novelty.maps.cells`); the scan's novelty is the mean of the
            ``top`` largest.
        """
        self._check_fitted()
        out = self.explain(x)
        return out["centres"], out["novelty"]

    def seen_share(self, X) -> np.ndarray:
        """Per scan, how much of its novelty lay in cells the map had evidence for (passed or hit before).

        The share of the scan's score (the sum of ``v`` over its ``top`` cells) that comes from such cells:
        1 where all of it did, 0 where the map had never seen any of the cells that make it (a place never
        seen: "never seen here" rather than "new here"); 1 for a scan that scores 0. Read one scan at a time
        by :meth:`explain` (the numpy reference: for studies and alarms, not a robot's loop).
        """
        self._check_fitted()
        return np.array([self.explain(x)["seen_share"] for x in np.asarray(X, dtype=np.float64)])

    def read_cells(self, cells) -> dict:
        """What the map holds of cells (i, j) (an array (m, 2)): ``efficacy`` (a fresh synapse's where it met
        none), ``passes`` and ``last_hit`` (0 where it met none)."""
        self._check_fitted()
        cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
        with self._own_call():
            units = self.clusterer_.index().units(cells[:, 0], cells[:, 1])
        held, at = units >= 0, np.maximum(units, 0)
        c, s = self.clusterer_, self.synapse_
        return {"efficacy": np.where(held, s.efficacy_[at] if s.efficacy_.size else 0.0, s.fresh_efficacy),
                "passes": np.where(held, c.passes_[at] if c.passes_.size else 0.0, 0.0),
                "last_hit": np.where(held, c.last_hit_[at] if c.last_hit_.size else 0, 0)}

    # ------------------------------------------------------------------ the state
    def _check_parts(self) -> None:
        for name, kind in (("clusterer_", "clusterer"), ("synapse_", "synapse")):
            part = getattr(self, name, None)
            if not (isinstance(part, Component) and part._kind == kind):
                raise StateError(f"{type(self).__name__}.{name} must be a {kind}; got {type(part).__name__}.")
        if not isinstance(self.clusterer_, WorldCells):
            raise StateError(f"{type(self).__name__}.clusterer_ must be a WorldCells; got "
                             f"{type(self.clusterer_).__name__}.")
        for part in (self.clusterer_, self.synapse_):
            try:
                part._validate_params()
            except ValueError as exc:
                raise StateError(f"{type(self).__name__}: {exc}") from None
            part._check_state()
        units = self.clusterer_.n_units_
        if self.synapse_.n_units_ != units:
            raise StateError(f"{type(self).__name__}.synapse_ has {self.synapse_.n_units_} synapses; its map "
                             f"holds {units} cells (256 a tile).")
        self.synapse_.check_efficacy(float(self.stimulus))
        pending = self.clusterer_.pending_
        if pending.ndim != 2 or (pending.shape[0] and pending.shape[1] != self.n_features_in_):
            raise StateError(f"{type(self).__name__}.clusterer_.pending_ must have shape (n, "
                             f"{self.n_features_in_}).")

    def _check_state(self) -> None:
        super()._check_state()
        self._check_parts()
        if (self.n_features_in_ - 3) % 3 or self.n_features_in_ < 6:
            raise StateError(f"{type(self).__name__}.n_features_in_ must be 3 + 3n (the 'points' input); "
                             f"got {self.n_features_in_}.")
        check_int_state(self.clusterer_, "scans_")


def _seen_share(v: np.ndarray, scoring: np.ndarray, seen: np.ndarray) -> float:
    total = float(v[scoring].sum())
    return 1.0 if total == 0 else float(v[scoring & seen].sum()) / total


#: The settings of ``habituating-map``, every one written out, so that the preset stays what was chosen
#: whatever the classes' defaults become (studies/maps)
HABITUATING_MAP = {"cell_size": 0.1, "evidence": "free", "free_scale": 2.0, "unseen": 0.25, "top": 2,
                   "tolerance": 1, "min_passes": 0, "evidence_lag": 0, "visit_gap": 10, "arc": "sector",
                   "neighbours": False, "tau_winner": 3.33, "alpha": 1.05}

#: The settings of ``map-explore``, every one written out (studies/maps)
MAP_EXPLORE = {"cell_size": 0.2, "evidence": "free", "free_scale": 2.0, "unseen": 0.5, "top": 3,
               "tolerance": 0, "min_passes": 0, "evidence_lag": 0, "visit_gap": 0, "arc": 0.0,
               "neighbours": False, "tau_winner": 3.33, "alpha": 1.05}


def habituating_map(**params) -> HabituatingMap:
    """A habituating map with Stanley's synapse (ours; the ``points`` input): :data:`HABITUATING_MAP`.

    Cells of 0.1 m read with their neighbours (``tolerance=1``), each sector a
    cone as wide as it stands for (``arc="sector"``), free-space evidence with
    a cell never passed weighing ``unseen=0.25``, the two most novel hit cells
    (``top=2``), a cell stimulated once a visit (``visit_gap=10``), the
    paper's synapse (``tau_winner=3.33``, ``alpha=1.05``). Any parameter given
    replaces its value, going to the part that takes it (``synapse=`` another
    synapse); ``tau`` and ``tau_neighbour`` as the map took them before it
    composed a synapse. Chosen in studies/maps.
    """
    return HabituatingMap.from_params(**{**HABITUATING_MAP, **_settings(params)})


def map_explore(**params) -> HabituatingMap:
    """A habituating map for a robot that explores and knows its pose (ours; the ``points`` input): :data:`MAP_EXPLORE`.

    Cells of 0.2 m, each read alone (``tolerance=0``) on its axis (``arc=0``),
    free-space evidence with a cell never passed weighing ``unseen=0.5``, the
    three most novel hit cells, one step a scan (``visit_gap=0``), the
    paper's synapse. Any parameter given replaces its value, as in
    :func:`habituating_map`. Chosen in studies/maps (the answer of "Which
    detector?" for a robot that keeps learning).
    """
    return HabituatingMap.from_params(**{**MAP_EXPLORE, **_settings(params)})
