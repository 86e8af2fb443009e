"""The synapse's efficacy is the novelty, on [0, 1]: a filter's synapse and stimulus are refused
when they would take it out.

A synapse says where its efficacy stays while every stimulus lies in ``[0,
S]`` (:meth:`novelty.habituation.base.Synapse.efficacy_range`; Stanley's
model: between its fixed point ``y0 - S / alpha`` and ``y0``). The filter
checks its synapse template (:func:`check_template`) with its parameters, and
its fitted synapse (:func:`check`) when one is set after fitting.
"""

from __future__ import annotations

import numpy as np

from ..habituation.base import Synapse
from ..registry import build, of_kind

__all__ = ["check", "check_template"]

#: roundings (of a double's epsilon, on the unit interval) by which a synapse's range of
#: efficacy may leave [0, 1] and still be taken to stay in it: ``y0 - S / alpha`` with
#: ``S = fl(alpha * y0)`` is within two of 0 (a rounding in the product, one in the quotient)
ROUNDINGS = 4

#: (name, registered factory, stimulus) of the named synapses whose range passed
_NAMED_PASSED: set = set()


def check_template(detector) -> None:
    """Refuse ``detector``'s synapse template (an instance, or a registered name built with its
    defaults) if under its stimulus its efficacy leaves [0, 1], after its own parameters."""
    if isinstance(detector.synapse, Synapse):
        detector.synapse._validate_params()
        check(detector.synapse, detector.stimulus)
        return
    # A registered name's synapse, with its defaults, is one value per factory: its range
    # under a stimulus is checked once (building it at every call was a large share of a
    # one-scan stream: docs/guide/performance.md)
    key = (detector.synapse, of_kind("synapse").get(detector.synapse), float(detector.stimulus)) \
        if isinstance(detector.synapse, str) else None
    try:
        if key in _NAMED_PASSED:
            return
    except TypeError:  # a factory that cannot be hashed: checked every time
        key = None
    synapse = build("synapse", detector.synapse)
    synapse._validate_params()
    check(synapse, detector.stimulus)
    if key is not None:
        if len(_NAMED_PASSED) > 256:  # stimuli made afresh for each call: bounded
            _NAMED_PASSED.clear()
        _NAMED_PASSED.add(key)


def check(synapse: Synapse, stimulus) -> None:
    """Refuse ``synapse`` if under ``stimulus`` its efficacy leaves [0, 1] (module docstring)."""
    low, high = synapse.efficacy_range(float(stimulus))
    # a bound that leaves [0, 1] by roundings only is kept: S written as alpha * y0 rounds
    # to either side of Stanley's fixed point (y0 - S / alpha = -1.1e-16 for alpha = 1.72,
    # y0 = 0.956: about 6 % of pairs), and an efficacy a few roundings below 0 is what the
    # model reaches at S = alpha * y0 anyway (and loads: the checks of a model file allow it)
    slack = ROUNDINGS * np.finfo(np.float64).eps
    if (np.isfinite(low) and low < -slack) or (np.isfinite(high) and high > 1 + slack):
        raise ValueError(
            f"The synapse's efficacy is the novelty, on [0, 1]; {synapse!r} under the stimulus "
            f"S = {stimulus} ranges over [{low:.6g}, {high:.6g}], which leaves it. Keep y0 <= 1 and "
            f"S <= alpha * y0 (Stanley's fixed point y0 - S / alpha >= 0): a smaller stimulus, a larger "
            "alpha, or a smaller y0."
        )
