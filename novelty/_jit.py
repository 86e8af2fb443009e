"""numba's decorator as every step function uses it, and compiling a pure function written elsewhere.

The components write their equations as plain Python functions (run by the
reference on numpy arrays); the step modules compile them with
:func:`compiled`. This module imports numba: only step modules and drivers
import it.
"""

from __future__ import annotations

import types

from numba import njit

#: the options of every step function: no Python division checks (the
#: validated parameters never divide by zero), inlined into the driver that
#: calls it (so importing a step module compiles nothing, and LLVM sees the
#: whole loop); cached where compiled alone
STEP = dict(cache=True, error_model="numpy", inline="always")

step = njit(**STEP)


def compiled(func, **callees):
    """``func`` compiled as a step function, with the plain functions it calls (its
    globals named in ``callees``) replaced by their compiled versions.

    numba compiles a call only to a compiled function; the component's module
    keeps its plain functions (it must import without numba), so the compiled
    copy looks them up in a namespace of its own.
    """
    if callees:
        namespace = dict(func.__globals__)
        namespace.update(callees)
        func = types.FunctionType(func.__code__, namespace, func.__name__, func.__defaults__,
                                  func.__closure__)
        # numba's disk cache keys on a module's source: a function with a namespace of its
        # own is not cached alone, only within the drivers that call it. Not inlined: such
        # functions are the larger ones (array code), inlined they compile many times slower.
        return njit(error_model="numpy")(func)
    return step(func)
