"""Four neighbouring weights moved in one vector, which numba's loops cannot express.

numba lets LLVM vectorise loops only (its straight-line vectoriser is off),
so a short run of neighbouring values, such as the three units of a SOM's
grid row moved towards a scan, stays one value at a time: :func:`move_four`
moves four neighbouring columns of a row in one vector (the online HSOM's
stream measurably faster than with :func:`move_four_plain`:
docs/guide/performance.md).

The vector is written in LLVM's own terms through numba's extension API
(:func:`numba.extending.intrinsic`), with opaque pointers as llvmlite's
deprecation notes ask (``ir.PointerType()``, and ``load`` told the type it
reads), so that it survives llvmlite's removal of typed pointers. It is one of
the kernels' tricks (:mod:`.tricks`): used only while their self-check passes,
else :func:`move_four_plain` is ``move_four``.

Exactness: each lane does the scalar code's IEEE operations, in its order,
with no fast-math flag, so the results are the scalar code's bit for bit.
Both are inlined where they are called, so importing this module compiles
nothing.
"""

from __future__ import annotations

import llvmlite.ir as ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from . import tricks

__all__ = ["move_four", "move_four_vector", "move_four_plain"]

_I32 = ir.IntType(32)
_I64 = ir.IntType(64)
_LANES = 4
_VECTOR = ir.VectorType(ir.DoubleType(), _LANES)


def _splat(builder, value, vector_type):
    one = builder.insert_element(ir.Constant(vector_type, ir.Undefined), value, ir.Constant(_I32, 0))
    return builder.shuffle_vector(one, one, ir.Constant(ir.VectorType(_I32, vector_type.count),
                                                        [0] * vector_type.count))


def _vector_pointer(builder, at):
    """``at`` as the pointer the four doubles are loaded from and stored to: itself where the IR
    has opaque pointers (llvmlite's future, ``LLVMLITE_ENABLE_IR_LAYER_TYPED_POINTERS=0`` today:
    the load names the type it reads), a pointer to the vector while numba's IR has typed ones
    (llvmlite's store checks the pointer's type against the value's)."""
    if at.type.is_opaque:
        return at
    return builder.bitcast(at, ir.PointerType(_VECTOR))


@intrinsic
def move_four_vector(typingctx, WT, f, j0, x, r0, r1, r2, r3, count):
    """``WT[f, j0 + q]`` moved towards ``x`` by ``r_q`` (``w + r_q * (x - w)``, as
    :func:`~novelty.clusterers.base.move_towards`) for the lanes ``q < count``; the
    others of the four written back unchanged. ``WT`` a C-contiguous float64 matrix, and
    the caller's promise: ``0 <= f < WT.shape[0]``, ``0 <= j0`` and ``j0 + 4 <= WT.shape[1]``.
    """
    if not (isinstance(WT, types.Array) and WT.ndim == 2 and WT.dtype == types.float64
            and WT.layout == "C"):
        return None
    sig = types.void(WT, types.int64, types.int64, types.float64, types.float64, types.float64,
                     types.float64, types.float64, types.int64)

    def codegen(context, builder, signature, args):
        matrix, row, column, target, a0, a1, a2, a3, lanes = args
        array = context.make_array(signature.args[0])(context, builder, matrix)
        at = cgutils.get_item_pointer(context, builder, signature.args[0], array, [row, column],
                                      wraparound=False)
        at = _vector_pointer(builder, at)
        w = builder.load(at, typ=_VECTOR, align=8)
        rates = ir.Constant(_VECTOR, ir.Undefined)
        for q, rate in enumerate((a0, a1, a2, a3)):
            rates = builder.insert_element(rates, rate, ir.Constant(_I32, q))
        moved = builder.fadd(w, builder.fmul(rates, builder.fsub(_splat(builder, target, _VECTOR), w)))
        inside = builder.icmp_signed("<", ir.Constant(ir.VectorType(_I64, _LANES), list(range(_LANES))),
                                     _splat(builder, lanes, ir.VectorType(_I64, _LANES)))
        builder.store(builder.select(inside, moved, w), at, align=8)
        return context.get_dummy_value()

    return sig, codegen


@njit(cache=True, error_model="numpy", inline="always")
def move_four_plain(WT, f, j0, x, r0, r1, r2, r3, count):
    """:func:`move_four_vector` one value at a time: the plain kernel's, and the self-check's
    reference."""
    if count > 0:
        WT[f, j0] = WT[f, j0] + r0 * (x - WT[f, j0])
    if count > 1:
        WT[f, j0 + 1] = WT[f, j0 + 1] + r1 * (x - WT[f, j0 + 1])
    if count > 2:
        WT[f, j0 + 2] = WT[f, j0 + 2] + r2 * (x - WT[f, j0 + 2])
    if count > 3:
        WT[f, j0 + 3] = WT[f, j0 + 3] + r3 * (x - WT[f, j0 + 3])


#: what the steps call: the vector while the tricks are in use (:mod:`.tricks`), else the plain one
move_four = move_four_vector if tricks.enabled() else move_four_plain
