"""From the reference to the compiled loop mid-stream, while the loop compiles.

The compiled engine gives the state the reference gives, so a stream can
switch from one to the other between two scans without a trace in the
results: while the pair's driver compiles in the background, the engine's
``learn`` runs the reference block by block and hands over as soon as the
driver is ready, taking the state the reference left into its own arrays.
"""

from __future__ import annotations

import numpy as np

from .reference import ReferenceEngine

__all__ = ["learn_handing_over"]

#: scans learned by the reference between two looks at the compiler thread
BLOCK = 256


def learn_handing_over(engine, compiling, X, dt, stimulus, distances=None) -> np.ndarray:
    """``engine.learn(X, dt, stimulus, distances)`` (a compiled engine) while ``compiling`` (its
    driver, a :class:`.compiling.Compiled`) compiles: the reference block by block, then, once
    the driver is ready, the driver on the state the reference left."""
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
