"""The rules a component's parameters follow, for plugin authors (``_parameter_rules``).

A component class maps each parameter name to a rule, or to a tuple of rules
any of which may accept; ``fit`` (and every call that learns) checks the
parameters against them, with one message form for the whole project::

    The 'max_age' parameter of GrowingNeuralGas must be an int in [1, inf). Got 0 instead.

>>> import numbers
>>> from novelty.rules import Interval, Options
>>> Interval(numbers.Real, 0, None, closed="neither").accepts(0.0)
False
>>> Options(("hold", "forget")).describe()
"one of 'hold', 'forget'"

Every parameter needs a rule: the conformance suite checks it
(:func:`novelty.testing.check_conformance`). The rule also says how compiled steps
read the parameter (a field of their record ``p``, see the guide's page on the
compiled loop); an option string is read as an int, :func:`option_code`:

>>> from novelty import SOM
>>> option_code(SOM, "decay", "linear")
1
"""

from ._kernels.params import option_code
from ._validation.parameters import Bounds, Instance, Interval, Options, validate_parameters

__all__ = ["Interval", "Options", "Instance", "Bounds", "validate_parameters", "option_code"]
