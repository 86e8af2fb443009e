"""The compiled steps of habituation that other components compose with.

A component whose compiled steps habituate a bank of its own runs the
synapses' schedule (:func:`stimulate`, :func:`fire`: who is stimulated, and
when; :mod:`novelty.habituation._schedule`) with a synapse's equation: the
Grow-When-Required network's firing counters are a Stanley bank
(``KernelSpec.nested``), whose equation is :mod:`stanley_steps
<novelty.habituation._stanley_steps>`. Imported from here, so that the step
modules stay this package's own.
"""

from __future__ import annotations

from . import _stanley_steps as stanley_steps
from ._schedule import fire, stimulate

__all__ = ["fire", "stimulate", "stanley_steps"]
