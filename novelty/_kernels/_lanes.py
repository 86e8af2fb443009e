"""Lane-wise arithmetic that numba's loops cannot express, written in LLVM's own terms.

numba lets LLVM vectorise loops only (its straight-line vectoriser is off),
so a short run of neighbouring values, such as the three units of a SOM's
grid row moved towards a scan, stays one value at a time: :func:`move_four`
moves four neighbouring columns of a row in one vector. And the distances'
subtractions all go to the processor's adders while its multipliers idle
half the time: :func:`difference` lets half of them take the fused
multiply-add units, as ``fma(x, -1, w)``, where the processor has them.

Exactness: each lane does the scalar code's IEEE operations, in its order,
with no fast-math flag, so the results are the scalar code's bit for bit.
``fma(x, -1, w)`` rounds ``w + (-x)`` once, exactly as ``w - x`` does
(the product ``-x`` is exact), signed zeros included. Each function is
inlined where it is called, so importing this module compiles nothing.
"""

from __future__ import annotations

import llvmlite.ir as ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

_F64 = ir.DoubleType()
_I32 = ir.IntType(32)
_I64 = ir.IntType(64)
_LANES = 4
_VECTOR = ir.VectorType(_F64, _LANES)


def _splat(builder, value, vector_type):
    one = builder.insert_element(ir.Constant(vector_type, ir.Undefined), value, ir.Constant(_I32, 0))
    return builder.shuffle_vector(one, one, ir.Constant(ir.VectorType(_I32, vector_type.count),
                                                        [0] * vector_type.count))


@intrinsic
def move_four(typingctx, WT, f, j0, x, r0, r1, r2, r3, count):
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
        at = builder.bitcast(at, _VECTOR.as_pointer())
        w = builder.load(at, align=8)
        rates = ir.Constant(_VECTOR, ir.Undefined)
        for q, rate in enumerate((a0, a1, a2, a3)):
            rates = builder.insert_element(rates, rate, ir.Constant(_I32, q))
        moved = builder.fadd(w, builder.fmul(rates, builder.fsub(_splat(builder, target, _VECTOR), w)))
        inside = builder.icmp_signed("<", ir.Constant(ir.VectorType(_I64, _LANES), list(range(_LANES))),
                                     _splat(builder, lanes, ir.VectorType(_I64, _LANES)))
        builder.store(builder.select(inside, moved, w), at, align=8)
        return context.get_dummy_value()

    return sig, codegen


def _fused(context) -> bool:
    """Whether the code is compiled for an x86 processor with fused multiply-add units (elsewhere
    ``fma`` may be a slow library call, or share the adders' units: nothing to gain)."""
    triple, _, features = context.codegen().magic_tuple()
    return triple.startswith(("x86_64", "i386", "i686")) and "+fma" in features.split(",")


@intrinsic
def minus_one(typingctx):
    """-1.0, which LLVM may not take for a constant where :func:`difference` fuses (it would
    turn ``fma(x, -1, w)`` back into a subtraction): passed through an empty assembly
    statement, which it cannot see into."""
    def codegen(context, builder, signature, args):
        if not _fused(context):
            return ir.Constant(_F64, -1.0)
        return builder.asm(ir.FunctionType(_F64, [_F64]), "", "=x,0", [ir.Constant(_F64, -1.0)],
                           side_effect=False)

    return types.float64(), codegen


@intrinsic
def difference(typingctx, w, x, minus):
    """``w - x``; computed as ``fma(x, minus, w)`` where the processor fuses (``minus`` is
    :func:`minus_one`), which rounds the same but runs on the multipliers' units."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        a, b, m = args
        if not _fused(context):
            return builder.fsub(a, b)
        fma = cgutils.get_or_insert_function(builder.module, ir.FunctionType(_F64, [_F64] * 3),
                                             "llvm.fma.f64")
        return builder.call(fma, [b, m, a])

    return sig, codegen
