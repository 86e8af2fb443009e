"""Arrays without a reference count, for the drivers' loops (see :mod:`novelty._kernels.drivers`).

numba counts the references to an array's memory: every array handed to an
inlined step function is counted in and out again, and numba's pruning of
those pairs gives up on loops, so a driver's loop did some twenty atomic
operations a scan (the online HSOM's stream measurably slower with them:
docs/guide/performance.md). :func:`uncounted_aliases` gives
aliases that numba does not count (no memory owner: counting one is a test
for null), and views of them are not counted either. The caller keeps the
owners alive until the loop is done, and lets no alias outlive them
(:func:`held`).

This leans on numba's internals (an array's ``meminfo`` field, and NRT
skipping a null one): if numba changed either, the result would be a
use-after-free, not an error. So it is one of the kernels' tricks
(:mod:`.tricks`), used only while their self-check passes; else
:func:`counted` (the arrays as they are, counted as numba counts them) is
``uncounted``.
"""

from __future__ import annotations

from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from . import tricks

__all__ = ["uncounted", "uncounted_aliases", "counted", "held"]


def _uncounted(context, builder, ty, value):
    if not isinstance(ty, types.Array):
        return value
    array = context.make_array(ty)(context, builder, value=value)
    array.meminfo = cgutils.get_null_value(array.meminfo.type)
    return array._getvalue()


@intrinsic
def uncounted_aliases(typingctx, arrays):
    """The arrays of the tuple ``arrays`` (other items as they are), not counted."""
    if not isinstance(arrays, types.BaseTuple):
        return None

    def codegen(context, builder, signature, args):
        ty = signature.args[0]
        out = args[0]
        for i, item in enumerate(ty.types):
            value = builder.extract_value(out, i)
            out = builder.insert_value(out, _uncounted(context, builder, item, value), i)
        return out

    return arrays(arrays), codegen


@njit(cache=True, error_model="numpy", inline="always")
def counted(arrays):
    """The tuple ``arrays`` as it is: the plain kernel's :func:`uncounted`."""
    return arrays


@njit(cache=True, error_model="numpy")
def held(owners):
    """Nothing: called after a loop on :func:`uncounted` aliases, with the arrays they alias, so
    that numba keeps those (it frees an array after its last use)."""


#: what the drivers call: uncounted aliases while the tricks are in use (:mod:`.tricks`)
uncounted = uncounted_aliases if tricks.enabled() else counted
