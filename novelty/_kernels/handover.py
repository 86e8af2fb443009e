"""From the reference to the compiled loop mid-stream, while the loop compiles.

The compiled engine gives the state the reference gives, so a stream can
switch from one to the other between two scans without a trace in the
results: while the pair's driver compiles in the background, the engine's
``learn`` runs the reference block by block and hands over as soon as the
driver is ready, taking the state the reference left into its own arrays.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .reference import ReferenceEngine

__all__ = ["handing_over"]

#: scans learned by the reference between two looks at the compiler thread
BLOCK = 256


def handing_over(compiling, engine) -> Callable:
    """``learn(X, dt, stimulus, distances=None)`` for ``engine`` (a compiled engine) while
    ``compiling`` (its driver, a :class:`.compiling.Compiled`) compiles."""

    def learn(X, dt, stimulus, distances=None):
        novelty = np.empty(X.shape[0])
        d = np.empty(X.shape[0]) if distances is None else distances
        start = 0
        while start < X.shape[0]:
            if compiling.module is not None or compiling.get() is not None:
                engine.start_driving(compiling)
                novelty[start:] = engine.learn(X[start:], dt[start:], stimulus, d[start:])
                break
            stop = start + BLOCK
            novelty[start:stop] = ReferenceEngine.learn(engine, X[start:stop], dt[start:stop], stimulus,
                                                        d[start:stop])
            start = stop
        return novelty

    return learn
