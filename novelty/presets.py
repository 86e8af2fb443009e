"""Registered combinations of a clusterer and a synapse, each by one name.

Each factory builds a :class:`~novelty.filter.HabituatingFilter` with the
components' own defaults (documented in their modules), except that the
growing networks (GNG, GWR) start from units drawn uniformly in [0, 1]^d
(``init="uniform"``: the inputs are scaled sonar readings) instead of rows
of the first batch, so that streaming scan by scan and in batches give the
same novelty; ``kmeans-stanley`` places its units on the scans learned
(``init="first"``), which is the same both ways too. Any
parameter goes to the part that takes it, as
:meth:`~novelty.filter.HabituatingFilter.from_params` does, e.g.
``novelty.make("gwr-wang-hsu", activity_threshold=0.9, beta=1.5)``.
``hsom`` (the paper's detector) lives in :mod:`novelty.filter`.

Every preset but ``hsom`` is scored by habituation x mismatch
(``novelty_rule="mismatch"``, our extension, see :mod:`novelty.match_scale`;
``gwr-explore`` and its variants: the ``"product"`` rule), with each network set up to match a
stream of scans closely (ours too); the
synapses keep the property this family exists for, that a feature's novelty
falls with each exposure. The published variants are reachable by
parameters: ``novelty_rule="efficacy"`` (the paper's novelty) and, for the
networks, the values each docstring gives. ``hsom-mismatch`` is the paper's
HSOM with the mismatch novelty.

A name whose clusterer is not registered (a plugin not installed) still
builds: the clusterer is then kept by name and looked up in ``fit``, which
says which name is missing.
"""

from __future__ import annotations

from .context import SequenceContext
from .filter import HabituatingFilter
from .registry import clusterers

__all__ = ["explore", "gwr_novelty", "gwr_explore", "gwr_explore_wang_hsu", "gwr_explore_staddon_higa", "gng_stanley", "som_wang_hsu", "gwr_wang_hsu",
           "gng_wang_hsu", "hsom_mismatch", "kmeans_stanley"]


#: Growing networks start from units drawn uniformly in [0, 1]^d (the range of
#: scaled sonar readings) rather than from rows of the first batch, so that a
#: detector streamed scan by scan and one fed whole batches start alike.
_GROWING = {"clusterer__init": "uniform"}

_MISMATCH = {"novelty_rule": "mismatch"}

#: k-means as a novelty filter's clusterer (ours): a unit placed on each scan
#: farther than the match scale from every unit (up to 400; the same scan by scan
#: and in batches), each the running mean of what it wins; the match scale a
#: Parzen window would take
_KMEANS_NOVELTY = {**_MISMATCH, "n_clusters": 400, "init": "first", "placement_radius": "auto",
                   "learning_rate": "count", "match_scale": "scott"}

#: GWR as a novelty detector (ours): a unit for every input farther than the
#: calibrated radius, which then stands for that input as its winner
_GWR_NOVELTY = {**_GROWING, **_MISMATCH, "activity_threshold": "auto", "firing_condition": False,
                "new_unit_wins": True}

#: GWR for exploration (ours): fewer, wider units, so that a recurring feature is
#: matched by the units its first encounter made; scored by habituation *and*
#: mismatch, with faster-habituating synapses
_GWR_EXPLORE = {**_GWR_NOVELTY, "insertion_radius": 1.5, "novelty_rule": "product",
                "tau_winner": 2.0}

#: gwr-explore's network and rule with Wang-Hsu synapses whose long-term memory builds fast
_GWR_EXPLORE_WANG_HSU = {**_GWR_NOVELTY, "insertion_radius": 1.5, "novelty_rule": "product",
                         "tau_winner": 5.0, "beta": 3.0, "gamma": 0.9}

#: gwr-explore's network, rule and winner's time constant with Staddon & Higa's two-unit cascade
_GWR_EXPLORE_STADDON_HIGA = {**_GWR_NOVELTY, "insertion_radius": 1.5, "novelty_rule": "product",
                             "tau_winner": 2.0}

#: GNG that grows at the pace of a robot's stream: a unit every 10 inputs
#: (Fritzke's lambda = 100 leaves 6 units after 300 scans)
_GNG_NOVELTY = {**_GROWING, **_MISMATCH, "insertion_interval": 10}


def _compose(clusterer: str, synapse: str, params: dict, defaults: dict | None = None) -> HabituatingFilter:
    if clusterer not in clusterers and not params:
        return HabituatingFilter(clusterer=clusterer, synapse=synapse)
    return HabituatingFilter.from_params(clusterer=clusterer, synapse=synapse, **{**(defaults or {}), **params})


def gwr_novelty(**params) -> HabituatingFilter:
    """Grow-When-Required network with Stanley synapses, a unit for each scan beyond a calibrated radius.

    The growing novelty filter of Marsland, Shapiro & Nehmzow (2002): the
    GWR network (``gwr``) in place of the SOM, each unit feeding the output
    through a Stanley synapse with the 2000 paper's values (tau = 3.33
    winner, 14.3 neighbours, alpha = 1.05, no forgetting); the GWR's own
    firing counters, which decide its growth, are separate synapses inside
    the network. Set up for novelty (ours): ``activity_threshold="auto"``
    (a_T = exp(-sigma), sigma the filter's calibrated match scale),
    ``firing_condition=False`` (a unit for any scan beyond that radius,
    without waiting for the winner to fire often), ``new_unit_wins=True``
    (the new unit habituates for the scan that made it; a scan that would
    make one scores as new) and ``novelty_rule="mismatch"``. The published
    network: ``activity_threshold=0.85, firing_condition=True,
    new_unit_wins=False, novelty_rule="efficacy"``.
    """
    return _compose("gwr", "stanley", params, _GWR_NOVELTY)


def gwr_explore(**params) -> HabituatingFilter:
    """GWR for exploration: flags a new feature on first sight, then habituates to it as it recurs.

    ``gwr-novelty`` set up for a robot that keeps learning while it
    explores (ours):

    - ``insertion_radius=1.5``: a unit only for a scan farther than 1.5
      sigma from its winner (``gwr-novelty``: 1 sigma), so that the next
      encounters of a feature are matched by the units its first encounter
      made (about 70 units for 1,300 scans of corridor A instead of 170);
    - ``novelty_rule="product"``: ``n = y_s (1 - exp(-d^2 / (2 sigma^2)))``,
      high only for a scan that is far from its winner *and* won by an
      unhabituated unit (a fresh one for a scan that makes a unit);
    - ``tau_winner=2.0``: the winner's synapse habituates faster than the
      paper's 3.33 (one firing takes it from 1 to 0.5 instead of 0.7).

    What makes a recurring feature familiar: the units placed at it at its
    first encounter move onto it (the mismatch falls) and their synapses
    habituate (the efficacy falls). How the settings were chosen and what
    they measure: ``studies/exploration/``.
    """
    return _compose("gwr", "stanley", params, _GWR_EXPLORE)


def gwr_explore_wang_hsu(**params) -> HabituatingFilter:
    """``gwr-explore`` with Wang-Hsu synapses: a recurring feature habituates deeper each time it returns.

    The network and rule of ``gwr-explore`` (``insertion_radius=1.5``,
    ``novelty_rule="product"``, ``n = y_s (1 - exp(-d^2 / (2 sigma^2)))``)
    with each unit's synapse the long-term-memory model of Wang & Hsu (1990,
    ``wang-hsu``)::

        tau dy/dt = alpha z (y0 - y) - beta y S
            dz/dt = gamma z (z - l) S

    Every stimulation lowers the speed of recovery ``z``, so a unit that
    stands for a feature met before settles lower, ``alpha z y0 / (alpha z +
    beta S)``, and recovers more slowly (``som-wang-hsu`` shows the faster
    re-habituation). Set up for exploration (ours): ``tau_winner=5.0``,
    ``beta=3.0`` (habituation rate; ``tau_winner`` must be at least
    ``alpha l + beta`` for the Euler step) and ``gamma=0.9`` (the Euler step
    needs ``gamma < 1 / l``); Wang & Hsu's other values as ``wang-hsu`` has
    them. How the settings were chosen: ``studies/exploration/``.
    """
    return _compose("gwr", "wang-hsu", params, _GWR_EXPLORE_WANG_HSU)


def gwr_explore_staddon_higa(**params) -> HabituatingFilter:
    """``gwr-explore`` with synapses that habituate at two time scales (Staddon & Higa 1996).

    The network, rule and winner's time constant of ``gwr-explore``
    (``insertion_radius=1.5``, ``novelty_rule="product"``, ``tau_winner=2.0``)
    with each unit's synapse the two-unit cascade of ``staddon-higa``::

        F <- a_f F + b_f S,   L <- a_s L + b_s max(0, S - F),   y = max(0, y0 - F - L)

    a fast memory ``F`` (time constant ``tau``) and a slow one ``L`` (10 tau)
    that learns only what the fast one lets through. A unit that wins a
    stretch of scans falls fast to about ``y0 - c_f = 0.2`` and then, more
    slowly, towards 0.04, so a feature met again keeps getting more familiar
    after the fast memory has done its part. The synapse's own defaults
    otherwise (gains 0.8, ``others="hold"``; ours). With ``others="forget"``
    the slow memory makes forgetting rate-sensitive (what that does on the
    exploration tasks: ``studies/exploration/``). Given the recent past it is
    ``explore``.
    """
    return _compose("gwr", "staddon-higa", params, _GWR_EXPLORE_STADDON_HIGA)


def gng_stanley(**params) -> HabituatingFilter:
    """Growing Neural Gas (Fritzke 1995) with Stanley synapses, growing a unit every 10 scans.

    The paper's proposed cure for the SOM's fixed size (Marsland et al.
    2000, section 5): ``gng`` with Stanley synapses with the paper's
    values. Set up for streams of hundreds to thousands of scans (ours):
    ``insertion_interval=10`` (Fritzke's lambda = 100 leaves 6 units after
    300 scans; 10 reaches the 100 units after 1,000) and
    ``novelty_rule="mismatch"``. Fritzke's network:
    ``insertion_interval=100, novelty_rule="efficacy"``.
    """
    return _compose("gng", "stanley", params, _GNG_NOVELTY)


def som_wang_hsu(**params) -> HabituatingFilter:
    """The paper's 10 x 10 SOM with Wang-Hsu long-term-memory synapses, habituation x mismatch.

    The HSOM of Marsland et al. (2000) with the synapse swapped for Wang &
    Hsu's (1990) model (``wang-hsu``), which re-habituates faster to what it
    has habituated to before; scored by habituation x mismatch (ours;
    ``novelty_rule="efficacy"``: the efficacy alone).
    """
    return _compose("som", "wang-hsu", params, _MISMATCH)


def gwr_wang_hsu(**params) -> HabituatingFilter:
    """Grow-When-Required network with Wang-Hsu long-term-memory synapses (set up as ``gwr-novelty``)."""
    return _compose("gwr", "wang-hsu", params, _GWR_NOVELTY)


def gng_wang_hsu(**params) -> HabituatingFilter:
    """Growing Neural Gas with Wang-Hsu long-term-memory synapses (set up as ``gng-stanley``)."""
    return _compose("gng", "wang-hsu", params, _GNG_NOVELTY)


def hsom_mismatch(**params) -> HabituatingFilter:
    """The paper's HSOM scored by habituation x mismatch: low only near a habituated unit (ours).

    ``hsom`` with ``novelty_rule="mismatch"``: the same 10 x 10 map and
    Stanley synapses, the novelty ``1 - (1 - y_s) exp(-d^2 / (2 sigma^2))``
    with sigma calibrated on the first 200 scans learned.
    """
    return _compose("som", "stanley", params, _MISMATCH)


def kmeans_stanley(**params) -> HabituatingFilter:
    """Online k-means with Stanley synapses, a unit for each scan beyond Scott's scale (ours).

    The simplest clusterer (``online-kmeans``, MacQueen 1967) in a novelty
    filter with Stanley synapses with the paper's values. Its units are
    placed on the scans themselves (``init="first"``): a scan farther than
    the match scale sigma from every unit becomes a unit
    (``placement_radius="auto"``, Hartigan's leader rule), up to
    ``n_clusters=400``; any other scan is learned by its winner, each unit
    the running mean of the scans it wins (``learning_rate="count"``). The
    novelty is habituation x mismatch (``novelty_rule="mismatch"``) with
    sigma Scott's bandwidth of the first 200 scans (``match_scale="scott"``,
    the bandwidth a Parzen window on them would take): low only within
    about a bandwidth of a unit that has won often. A scan that recurs gets
    a unit of its own at its first exposure and habituates from there.
    ``n_clusters=100, placement_radius=0`` is MacQueen's start (the first
    100 distinct scans).
    """
    return _compose("online-kmeans", "stanley", params, _KMEANS_NOVELTY)


#: the parameters ``explore`` gives its context stage; the rest go to the detector inside
_CONTEXT_PARAMS = ("delay", "lag", "differences", "smoothing", "threshold", "contamination")


def explore(**params) -> SequenceContext:
    """An exploring detector of the sonar ring that keeps learning (ours).

    ``gwr-explore-staddon-higa`` (``gwr-explore``'s network with synapses that
    habituate at two time scales, a fast and a slow memory in cascade, Staddon &
    Higa 1996) given the context of the recent past: a delay embedding of three
    scans two apart, ``(x_t, x_{t-2}, x_{t-4})``
    (:class:`~novelty.context.SequenceContext`, ``delay=3, lag=2``), so that a
    unit stands for a short stretch of the route rather than one scan.
    Parameters of the stage (``delay``, ``lag``, ``differences``,
    ``smoothing``, ``threshold``, ``contamination``) go to it, the others to
    ``gwr-explore-staddon-higa``. A scan's novelty depends on the scans before
    it, so scans must come in the order they were perceived.

    Chosen among the habituating detectors of the sonar ring by a rule
    written before its run: ``studies/exploration/``. For a robot that knows
    its pose with each scan, "Which detector?" answers
    :func:`~novelty.maps.habituating_map.map_explore` (docs/guide/which-detector.md).
    """
    context = {k: params.pop(k) for k in _CONTEXT_PARAMS if k in params}
    return SequenceContext(gwr_explore_staddon_higa(**params), **{"delay": 3, "lag": 2, **context})
