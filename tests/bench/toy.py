"""A tiny synthetic task and a detector that fails, for the harness tests.

Importable by worker processes (joblib, Dask), which get the test folder on
their path from the parent.
"""

from __future__ import annotations

import numpy as np

from novelty.datasets import Dataset

TASK = "bench-toy-task"
BROKEN = "bench-broken-detector"


def toy_task(seed=0, n_train=40, n_test=30, n_sensors=4, novel_at=12, novel_len=6, fail=False,
             clean="none"):
    """Normal scans near 0.3, a block of novel scans near 0.8 in the test part.

    ``clean="runs"``: the test part is two runs, the second without novelty;
    ``clean="metadata"``: the metadata holds a clean pass of 10 scans.
    """
    if fail:
        raise RuntimeError("the toy task was asked to fail")
    rng = np.random.default_rng(seed)
    train = 0.3 + 0.03 * rng.standard_normal((n_train, n_sensors))
    test = 0.3 + 0.03 * rng.standard_normal((n_test, n_sensors))
    y_test = np.zeros(n_test, dtype=int)
    y_test[novel_at:novel_at + novel_len] = 1
    test[y_test == 1] += 0.5
    X = np.vstack([train, test])
    y = np.r_[np.zeros(n_train, dtype=int), y_test]
    split = np.array(["train"] * n_train + ["test"] * n_test)
    distance = np.r_[np.arange(n_train), np.arange(n_test)] * 0.1
    metadata = {"train_passes": 2, "seed": seed}
    run = None
    if clean == "runs":
        run = np.r_[np.zeros(n_train, dtype=int), np.where(np.arange(n_test) < novel_at + novel_len + 2, 1, 2)]
    elif clean == "metadata":
        metadata["clean_test"] = 0.3 + 0.03 * rng.standard_normal((10, n_sensors))
    return Dataset(TASK, X, y=y, split=split, distance=distance, run=run, metadata=metadata)


def broken_detector(**params):
    """A detector whose training always fails."""
    import novelty

    det = novelty.make("hsom", **params)

    def fail(*args, **kwargs):
        raise FloatingPointError("this detector always fails")

    det.partial_fit = fail
    return det


EXPLORATION = "bench-toy-exploration"


def toy_exploration(seed=0, n_runs=6, n_scans=20, n_sensors=4):
    """Familiar scans near 0.3; a door (near 0.8) in every other run after the warm-up run."""
    from novelty.tasks.exploration import from_runs

    rng = np.random.default_rng(seed)
    runs, seen = [], []
    for r in range(n_runs):
        X = 0.3 + 0.03 * rng.standard_normal((n_scans, n_sensors))
        labels = [None] * n_scans
        if r % 2 == 1:
            X[5:9] += 0.5
            labels[5:9] = ["door"] * 4
        runs.append(X)
        seen.append(labels)
    return from_runs(runs, seen, warmup=1, name=EXPLORATION)
