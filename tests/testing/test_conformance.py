"""Every registered clusterer, synapse and detector passes the conformance suite.

The components are found through the registries, so a newly registered one
is checked here without new test code.
"""

import numpy as np
import pytest

import novelty
from novelty.registry import clusterers, synapses
from novelty.io.scans.points import example_rows
from novelty.testing import conformance_checks, installed_detectors

from ..registered import detector_params


def _cases():
    cases = []
    for registry in (clusterers, synapses):
        for name in registry.names():
            component = registry.make(name)
            cases += [pytest.param(check, id=f"{registry.kind}:{name}:{check.__name__}")
                      for check in conformance_checks(component)]
    for name in installed_detectors():
        det = novelty.make(name)
        cases += [pytest.param(check, id=f"detector:{name}:{check.__name__}")
                  for check in conformance_checks(det)]
    # a detector whose optional dependency is missing shows as skipped, with the extra to install
    cases += [pytest.param(None, marks=p.marks, id=f"detector:{p.values[0]}")
              for p in detector_params() if p.marks]
    return cases


@pytest.mark.parametrize("check", _cases())
def test_conformance(check):
    check()


def test_every_clusterer_with_every_synapse():
    """The whole cross-product composes and streams through the habituating filter (a map, for world cells)."""
    from novelty.testing.conformance import _data

    X = _data()
    for c in clusterers.names():
        for s in synapses.names():
            det = novelty.make("habituating", clusterer=c, synapse=s)
            if getattr(det, "input_layout", None) == "points":   # world cells: a map of the points input
                out = det.stream(example_rows(seed=1, n=40))
                assert out.shape == (40,) and np.all((out >= 0) & (out <= det.synapse_.y0)), (c, s)
                continue
            out = det.stream(X)
            rest = det.synapse_.resting_efficacy
            assert out.shape == (len(X),), (c, s)
            assert np.all((out >= rest - 1e-9) & (out <= det.synapse_.y0 + 1e-9)), (c, s)
            assert out[0] == det.synapse_.y0, f"{c}+{s}: the first scan is fully novel"
