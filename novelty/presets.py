"""Registered combinations of a clusterer and a synapse, each by one name.

Each factory builds a :class:`~novelty.filter.HabituatingFilter` with the
components' own defaults (documented in their modules), except that the
growing networks (GNG, GWR) start from units drawn uniformly in [0, 1]^d
(``init="uniform"``: the inputs are scaled sonar readings) instead of rows
of the first batch, so that streaming scan by scan and in batches give the
same novelty. Any parameter goes to the part that takes it, as
:meth:`~novelty.filter.HabituatingFilter.from_params` does, e.g.
``novelty.make("gwr-wang-hsu", activity_threshold=0.9, beta=1.5)``.
``hsom`` (the paper's detector) lives in :mod:`novelty.filter`.

A name whose clusterer is not registered (a plugin not installed) still
builds: the clusterer is then kept by name and looked up in ``fit``, which
says which name is missing.
"""

from __future__ import annotations

from .filter import HabituatingFilter

__all__ = ["gwr_novelty", "gng_stanley", "som_wang_hsu", "gwr_wang_hsu", "gng_wang_hsu"]


#: Growing networks start from units drawn uniformly in [0, 1]^d (the range of
#: scaled sonar readings) rather than from rows of the first batch, so that a
#: detector streamed scan by scan and one fed whole batches start alike.
_GROWING = {"clusterer__init": "uniform"}


def _compose(clusterer: str, synapse: str, params: dict, defaults: dict | None = None) -> HabituatingFilter:
    from .registry import clusterers

    if clusterer not in clusterers and not params:
        return HabituatingFilter(clusterer=clusterer, synapse=synapse)
    return HabituatingFilter.from_params(clusterer=clusterer, synapse=synapse, **{**(defaults or {}), **params})


def gwr_novelty(**params) -> HabituatingFilter:
    """Grow-When-Required network with Stanley synapses (Marsland, Shapiro & Nehmzow 2002).

    The authors' growing novelty filter: the GWR network (``gwr``, with the
    defaults its module documents) in place of the SOM, each unit feeding
    the output through a Stanley synapse with the 2000 paper's values
    (tau = 3.33 winner, 14.3 neighbours, alpha = 1.05, no forgetting). The
    GWR's own firing counters, which decide its growth, are separate
    synapses inside the network.
    """
    return _compose("gwr", "stanley", params, _GROWING)


def gng_stanley(**params) -> HabituatingFilter:
    """Growing Neural Gas (Fritzke 1995) with Stanley synapses.

    The paper's proposed cure for the SOM's fixed size (Marsland et al.
    2000, section 5): ``gng`` with its usual defaults, Stanley synapses with
    the paper's values.
    """
    return _compose("gng", "stanley", params, _GROWING)


def som_wang_hsu(**params) -> HabituatingFilter:
    """The paper's 10 x 10 SOM with Wang-Hsu long-term-memory synapses.

    The HSOM of Marsland et al. (2000) with the synapse swapped for Wang &
    Hsu's (1990) model (``wang-hsu``), which re-habituates faster to what it
    has habituated to before.
    """
    return _compose("som", "wang-hsu", params)


def gwr_wang_hsu(**params) -> HabituatingFilter:
    """Grow-When-Required network with Wang-Hsu long-term-memory synapses."""
    return _compose("gwr", "wang-hsu", params, _GROWING)


def gng_wang_hsu(**params) -> HabituatingFilter:
    """Growing Neural Gas with Wang-Hsu long-term-memory synapses."""
    return _compose("gng", "wang-hsu", params, _GROWING)
