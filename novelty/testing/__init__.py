"""Tools for testing components: the conformance suite plugin authors run.

>>> from novelty.testing import check_conformance
>>> from novelty.clusterers import SOM
>>> check_conformance(SOM(n_rows=3, n_columns=3))
"""

from .conformance import (check_compiled_equals_reference, check_conformance, check_kernel_declares_every_parameter,
                          check_rules_cover_every_parameter, conformance_checks, installed_detectors)

__all__ = ["check_conformance", "conformance_checks", "installed_detectors", "check_compiled_equals_reference",
           "check_rules_cover_every_parameter", "check_kernel_declares_every_parameter"]
