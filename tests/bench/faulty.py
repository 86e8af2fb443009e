"""Detectors that fail in every way a cell can: for the harness's failure handling.

Importable by worker processes (joblib, Dask), like ``toy``.
"""

from __future__ import annotations

import os
import time

import numpy as np

import novelty

CRASH, EXIT, HANG, NAN = "faulty-crash", "faulty-exit", "faulty-hang", "faulty-nan"
INTERRUPT = "faulty-interrupt"


def _hsom_failing(fail, **params):
    det = novelty.make("hsom", **params)
    det.partial_fit = fail
    return det


def crash(**params):
    """Its worker process dies mid-cell, as after a segfault or the OOM killer."""
    return _hsom_failing(lambda *a, **k: os._exit(3), **params)


def exit_(**params):
    """Training calls sys.exit."""
    def fail(*args, **kwargs):
        raise SystemExit(4)
    return _hsom_failing(fail, **params)


def interrupt(**params):
    """Training raises KeyboardInterrupt (as a library's own signal handling may)."""
    def fail(*args, **kwargs):
        raise KeyboardInterrupt
    return _hsom_failing(fail, **params)


def hang(**params):
    """Training never ends (in any reasonable time)."""
    return _hsom_failing(lambda *a, **k: time.sleep(600), **params)


def nan_on_seed_1(**params):
    """Scores NaN for one test scan, on seed 1 only."""
    det = novelty.make("hsom", **params)
    novelty_of = det.novelty

    def scores(X):
        out = novelty_of(X)
        if det.random_state == 1 and len(out) > 5:
            out = out.copy()
            out[5] = np.nan
        return out

    det.novelty = scores
    return det


FACTORIES = {CRASH: crash, EXIT: exit_, HANG: hang, NAN: nan_on_seed_1, INTERRUPT: interrupt}
