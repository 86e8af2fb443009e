"""From the reference to the kernel mid-stream, while the kernel compiles.

A kernel gives the same state as the reference, so a stream can switch from
one to the other between two scans without a trace in the results: the
stand-in runs the reference block by block and hands over as soon as the
kernel is ready.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["handing_over"]

#: scans learned by the reference between two looks at the compiler thread
BLOCK = 256


def handing_over(compiled, kernel: Callable, reference: Callable) -> Callable:
    """``kernel``'s stand-in while ``compiled`` (a :class:`.compiling.Compiled`) compiles."""

    def learn(net, syn, X, dt, stimulus, distances=None, winners=None):
        if winners is not None:  # only tests ask for winners, and they wait for the kernel
            raise ValueError("winners are only reported by the compiled kernel")
        novelty = np.empty(X.shape[0])
        d = np.empty(X.shape[0]) if distances is None else distances
        start = 0
        while start < X.shape[0]:
            if compiled.module is not None or compiled.get() is not None:
                novelty[start:] = kernel(net, syn, X[start:], dt[start:], stimulus,
                                         distances=d[start:])
                break
            stop = start + BLOCK
            novelty[start:stop] = reference(net, syn, X[start:stop], dt[start:stop], stimulus,
                                            distances=d[start:stop])
            start = stop
        return novelty

    return learn
