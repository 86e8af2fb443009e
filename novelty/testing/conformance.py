"""The conformance suite: checks every clusterer, synapse and detector must pass.

Plugin authors run it on their own components, the way scikit-learn's
``check_estimator`` is used::

    from novelty.testing import conformance_checks

    @pytest.mark.parametrize("check", conformance_checks(MyClusterer()), ids=lambda c: c.__name__)
    def test_my_clusterer(check):
        check()

or in one call, ``check_conformance(MyClusterer())``. The project's own test
suite runs it over every registered name, so a new component is checked
without new test code.

Each check builds what it needs from the component's parameters (it clones
the instance), so the instance given is never modified. The checks of each
kind are in :mod:`~novelty.testing.clusterer_checks`,
:mod:`~novelty.testing.synapse_checks`, :mod:`~novelty.testing.map_checks` (a clusterer of
world cells) and :mod:`~novelty.testing.detector_checks`.
"""

from __future__ import annotations

import functools
from typing import Callable, Iterator

from ..clusterers.base import Clusterer
from ..detector import NoveltyDetector
from ..habituation.base import Synapse
from ._helpers import N_FEATURES, _assert_same_state, _check, _data, _state_arrays  # noqa: F401  (read from here too)
from .._component import declares
from .._kernels.params import spec_of
from .compiled_checks import check_compiled_equals_reference, check_kernel_declares_every_parameter
from .clusterer_checks import (check_clusterer_adapt_moves_winner_closer, check_clusterer_deterministic,
                               check_clusterer_growth_is_consistent, check_clusterer_in_filter,
                               check_clusterer_initialize, check_clusterer_match, check_clusterer_match_is_pure,
                               check_clusterer_state_round_trip, check_clusterer_winners_equal_match)
from .detector_checks import (check_detector_calibrate, check_detector_deterministic, check_detector_fit_and_novelty,
                              check_detector_novelty_is_pure, check_detector_online,
                              check_detector_rejects_bad_input, check_detector_save_load, installed_detectors)
from .synapse_checks import (check_synapse_dt, check_synapse_forget_rule, check_synapse_grow_shrink,
                             check_synapse_habituates_and_is_bounded, check_synapse_hold_rule,
                             check_synapse_initialize)
from .map_checks import check_cells_start_empty, check_map_compiled_equals_reference, check_map_deterministic
from ..maps.cells import WorldCells

__all__ = ["conformance_checks", "check_conformance", "installed_detectors",
           "check_compiled_equals_reference", "check_rules_cover_every_parameter",
           "check_kernel_declares_every_parameter"]


def _named(fn: Callable, component) -> Callable:
    bound = functools.partial(fn, component)
    bound.__name__ = fn.__name__
    return bound


_CHECKS = {
    Clusterer: [
        check_clusterer_initialize,
        check_clusterer_deterministic,
        check_clusterer_match,
        check_clusterer_match_is_pure,
        check_clusterer_winners_equal_match,
        check_clusterer_adapt_moves_winner_closer,
        check_clusterer_growth_is_consistent,
        check_clusterer_state_round_trip,
        check_clusterer_in_filter,
    ],
    Synapse: [
        check_synapse_initialize,
        check_synapse_habituates_and_is_bounded,
        check_synapse_hold_rule,
        check_synapse_forget_rule,
        check_synapse_grow_shrink,
        check_synapse_dt,
    ],
    WorldCells: [
        check_cells_start_empty,
        check_map_deterministic,
        check_map_compiled_equals_reference,
    ],
    NoveltyDetector: [
        check_detector_fit_and_novelty,
        check_detector_novelty_is_pure,
        check_detector_deterministic,
        check_detector_rejects_bad_input,
        check_detector_online,
        check_detector_save_load,
        check_detector_calibrate,
    ],
}


@_check
def check_rules_cover_every_parameter(component) -> None:
    """Every parameter has a rule (``_parameter_rules``; :mod:`novelty.rules`), so that a
    wrong value is refused with a clear message before anything is learned."""
    rules = set(getattr(component, "_parameter_rules", {}))
    if isinstance(component, NoveltyDetector) and hasattr(component, "contamination"):
        rules.add("contamination")  # the base class's rule, for every detector
    missing = sorted(set(component.get_params(deep=False)) - rules)
    assert not missing, f"{type(component).__name__} has no rule for {missing} (_parameter_rules)"


def conformance_checks(component) -> Iterator[Callable[[], None]]:
    """The checks that apply to ``component``, each a no-argument callable.

    A clusterer or synapse whose class declares compiled steps, or a clusterer that declares
    nearest-unit scoring, is also checked against its reference
    (:func:`check_compiled_equals_reference`); one that declares compiled steps, for a field of
    their parameters' record for each parameter (:func:`check_kernel_declares_every_parameter`).
    """
    for base, checks in _CHECKS.items():
        if isinstance(component, base):
            for fn in checks:
                yield _named(fn, component)
            yield _named(check_rules_cover_every_parameter, component)
            if base is not NoveltyDetector and spec_of(component) is not None:
                yield _named(check_kernel_declares_every_parameter, component)
            if base in (Clusterer, Synapse) and (spec_of(component) is not None
                                                 or declares(component, "nearest-unit")):
                yield _named(check_compiled_equals_reference, component)
            return
    raise TypeError(f"{type(component).__name__} is not a Clusterer, Synapse, WorldCells or NoveltyDetector.")


def check_conformance(component) -> None:
    """Run every applicable check; raise AssertionError on the first failure (a check that
    cannot run here, the compiled one without numba, raises ``unittest.SkipTest``)."""
    for check in conformance_checks(component):
        try:
            check()
        except AssertionError as exc:
            raise AssertionError(f"{type(component).__name__} fails {check.__name__}: {exc}") from exc
