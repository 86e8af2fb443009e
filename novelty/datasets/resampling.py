"""Resampling protocols: how a labelled table of scans becomes a task, seed by seed.

A published benchmark states how each of its runs draws its data; the same
statement here is a :class:`Resampling`, given to the ``files`` task as
options (``novelty bench --task 'files path=6_cardio.npz resample=adbench'``)
or to :func:`resampled` for arrays in Python. Its steps, in this order:

1. ``min_rows``, ``max_rows`` (with ``resample`` only): a table of fewer than
   ``min_rows`` rows is bootstrapped up to ``min_rows`` (rows drawn with
   replacement), one of more than ``max_rows`` subsampled to ``max_rows``
   (without replacement), before the split, as ADBench does (Han et al.
   2022, section 4.1 and its code's data generator: so a bootstrapped row
   and its copies can fall on both sides of the split).
2. ``resample``: a train/test split drawn for each seed, ``stratified`` (each
   class split in the proportion ``test``, scikit-learn's
   ``train_test_split(..., stratify=y)``) or ``shuffled`` (rows split at
   random, classes as they fall), both drawn from a generator seeded by the
   seed and the task's name; or ``adbench``: steps 1 and 2 drawn exactly as
   ADBench's code draws them (:func:`adbench_split`), the same rows for the
   same seed. Without ``resample`` the task keeps the split its source gives
   (the first rows, a column, a second file).
3. ``training``: ``contaminated`` (the default: novel scans stay in the
   training part, unlabelled, as in unsupervised outlier detection and
   ADBench) or ``clean`` (novel scans are dropped from the training part:
   novelty detection, a detector learning only what is normal).
4. ``scale``: ``minmax`` or ``standard`` fitted on the training part (after
   step 3) and applied to both parts (scikit-learn's ``MinMaxScaler`` and
   ``StandardScaler``); ``none`` (the default) leaves the values as read.
   Test values may fall outside the training part's range.

``resample=adbench`` takes ADBench's values for the options not given
(:data:`ADBENCH_DEFAULTS`: ``test=0.3 min_rows=1000 max_rows=10000
scale=minmax``; ``training`` is ``contaminated`` by default anyway), so that
the one option is ADBench's unsupervised protocol; any option given
explicitly overrides its default.

:meth:`Resampling.describe` says all of it in one line, which the files task
keeps in its metadata (``split_description``) and the benchmark summary
prints for each task. :data:`ADBENCH` is ADBench's unsupervised protocol.

References
----------
Han, S., Hu, X., Huang, H., Jiang, M. & Zhao, Y. (2022). ADBench: anomaly
detection benchmark. NeurIPS 2022 Datasets and Benchmarks track.
"""

from __future__ import annotations

import hashlib
import numbers
from dataclasses import asdict, dataclass, replace

import numpy as np

from ..data import Dataset
from ..io.tables.labels import check_labels

__all__ = ["Resampling", "ResampledTask", "resampled", "adbench_split", "ADBENCH", "ADBENCH_DEFAULTS", "RESAMPLE",
           "SCALES", "TRAINING", "OPTIONS", "MAX_ROWS", "MAX_VALUES"]

#: the ways a split is drawn for each seed
RESAMPLE = ("stratified", "shuffled", "adbench")
#: the scalers fitted on the training part
SCALES = ("none", "minmax", "standard")
#: what the training part keeps of the novel scans
TRAINING = ("contaminated", "clean")
#: the option names, as the files task and :func:`resampled` take them
OPTIONS = ("resample", "test", "min_rows", "max_rows", "scale", "training")
#: the default test fraction of a drawn split
DEFAULT_TEST = 0.3
#: the most rows ``min_rows`` and ``max_rows`` say (ADBench's are 1,000 and 10,000)
MAX_ROWS = 2**24
#: the most values (rows x features) a bootstrapped table holds: 2**27 float64, 1 GiB, checked before it is drawn
MAX_VALUES = 2**27

#: the options ``resample="adbench"`` fills in when they are not given: ADBench's values
ADBENCH_DEFAULTS = {"test": 0.3, "min_rows": 1000, "max_rows": 10000, "scale": "minmax"}
#: ADBench's unsupervised protocol (Han et al. 2022), drawn as its code draws it: a stratified
#: 70/30 split for each seed, tables bootstrapped to 1,000 rows or subsampled to 10,000,
#: min-max scaled on the training part, anomalies left in the training part
ADBENCH = {"resample": "adbench", **ADBENCH_DEFAULTS, "training": "contaminated"}


def _scaler(name: str):
    # imported here: the files task is read by the command line, which starts without scikit-learn
    from sklearn.preprocessing import MinMaxScaler, StandardScaler

    return {"minmax": MinMaxScaler, "standard": StandardScaler}[name]()


def _choice(value, allowed: tuple, name: str, default: str) -> str:
    if value is None:
        return default
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(allowed)}; got {value!r}.")
    return value


def _count(value, name: str) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not 2 <= value <= MAX_ROWS:
        raise ValueError(f"{name} must be a number of rows, 2 to {MAX_ROWS:,}; got {value!r}.")
    return int(value)


@dataclass(frozen=True)
class Resampling:
    """A resampling protocol (see the module notes); :meth:`check` validates and fills the defaults."""

    resample: str | None = None
    test: float | None = None
    min_rows: int | None = None
    max_rows: int | None = None
    scale: str | None = None
    training: str | None = None

    def check(self) -> "Resampling":
        """This protocol with its defaults filled in; a bad option is a ``ValueError`` naming it."""
        if self.resample is not None and self.resample not in RESAMPLE:
            raise ValueError(f"resample must be one of {', '.join(RESAMPLE)}; got {self.resample!r}.")
        if self.resample == "adbench":
            return replace(self, **{k: v for k, v in ADBENCH_DEFAULTS.items() if getattr(self, k) is None})._checked()
        return self._checked()

    def _checked(self) -> "Resampling":
        drawn = self.resample is not None
        for name in ("test", "min_rows", "max_rows"):
            if getattr(self, name) is not None and not drawn:
                raise ValueError(f"{name}= sizes a split drawn for each seed; give resample=stratified, "
                                 "shuffled or adbench with it.")
        test = DEFAULT_TEST if self.test is None and drawn else self.test
        if test is not None and (isinstance(test, bool) or not isinstance(test, numbers.Real) or not 0 < test < 1):
            raise ValueError(f"test must be the fraction of rows tested, in (0, 1); got {test!r}.")
        low, high = _count(self.min_rows, "min_rows"), _count(self.max_rows, "max_rows")
        if low is not None and high is not None and low > high:
            raise ValueError(f"min_rows ({low}) must not exceed max_rows ({high}).")
        return Resampling(self.resample, None if test is None else float(test), low, high,
                          _choice(self.scale, SCALES, "scale", "none"),
                          _choice(self.training, TRAINING, "training", "contaminated"))

    @property
    def draws(self) -> bool:
        """Whether a split is drawn for each seed."""
        return self.resample is not None

    def as_options(self) -> dict:
        """The options, as the files task takes them (None left out)."""
        return {k: v for k, v in asdict(self).items() if v is not None}

    # ------------------------------------------------------------ the steps
    def draw(self, data: Dataset, seed: int) -> Dataset:
        """Steps 1 and 2: ``data`` resized and split for ``seed`` (training rows first)."""
        if data.y is None:
            raise ValueError(f"resample={self.resample} needs labels for every row (a y or label column).")
        y = check_labels(data.y, f"{data.name}, labels")
        if self.min_rows is not None and len(y) < self.min_rows and self.min_rows * data.n_sensors > MAX_VALUES:
            raise ValueError(f"min_rows={self.min_rows:,} rows of {data.n_sensors} features make "
                             f"{self.min_rows * data.n_sensors:,} values; at most {MAX_VALUES:,} are drawn.")
        if self.resample == "adbench":
            train, test = adbench_split(y, seed, self.test, self.min_rows, self.max_rows)
        else:
            train, test = self._split(y, seed, data.name)
        rows = np.concatenate([train, test])
        drawn = data.subset(rows)
        # drawn rows have no order: no route, no clock (a timestamp would run backwards)
        return replace(drawn, y=y[rows], distance=None, run=None, poses=None,
                       columns={k: v for k, v in drawn.columns.items() if k != "time"},
                       split=np.array(["train"] * len(train) + ["test"] * len(test)))

    def _split(self, y: np.ndarray, seed: int, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Steps 1 and 2 of ``stratified`` and ``shuffled``: drawn from the seed and the table's name."""
        # imported here: the command line reads the files task and starts without scikit-learn
        from sklearn.model_selection import train_test_split

        rng = np.random.default_rng(np.random.SeedSequence([int(seed), _tag(name)]))
        rows = _resized(rng, len(y), self.min_rows, self.max_rows)
        return train_test_split(rows, test_size=self.test, shuffle=True, random_state=int(rng.integers(2**31 - 1)),
                                stratify=y[rows] if self.resample == "stratified" else None)

    def finish(self, data: Dataset) -> Dataset:
        """Steps 3 and 4 on a split task: clean training, then the scaler fitted on the training part."""
        if self.training == "clean":
            if data.y is None:
                raise ValueError("training=clean drops the novel scans from the training part, which needs "
                                 "labels for the training rows.")
            data = data.subset(~((data.split == "train") & (np.asarray(data.y) != 0)))
        if self.scale not in (None, "none"):
            train = data.split == "train"
            scaler = _scaler(self.scale).fit(data.X[train])
            data = replace(data, X=scaler.transform(data.X))
        return data

    def apply(self, data: Dataset, seed: int = 0) -> Dataset:
        """Every step: ``data`` (a labelled table, or a task when nothing is drawn) as the task of ``seed``."""
        protocol = self.check()
        task = protocol.draw(data, seed) if protocol.draws else data
        if task.split is None:
            raise ValueError(f"{data.name}: no train/test split; give resample=stratified (or shuffled).")
        task = protocol.finish(task)
        meta = {**task.metadata, "resampling": protocol.as_options()}
        if protocol.draws:
            meta.update(seed=int(seed), route=False)
        return replace(task, metadata=meta)

    def describe(self, given: str = "") -> str:
        """One line: how the task's parts were drawn (``given``: the source's own split, when nothing is drawn)."""
        protocol = self.check()
        if protocol.draws:
            cut = f"{round(100 * (1 - protocol.test))}/{round(100 * protocol.test)}"
            parts = [f"a {protocol.resample} {cut} train/test split drawn for each seed" if protocol.resample != "adbench"
                     else f"a stratified {cut} train/test split drawn for each seed as ADBench's code draws it "
                          "(numpy's RandomState(seed))"]
            sizes = []
            if protocol.min_rows is not None:
                sizes.append(f"bootstrapped to {protocol.min_rows:,} rows when fewer")
            if protocol.max_rows is not None:
                sizes.append(f"subsampled to {protocol.max_rows:,} rows when more")
            if sizes:
                parts.append(" and ".join(sizes) + " (before the split)")
        else:
            parts = [given or "the split the task gives"]
        parts.append("novel scans dropped from training (clean: novelty detection)" if protocol.training == "clean"
                     else "novel scans kept in training, unlabelled (contaminated: outlier detection)")
        if protocol.scale != "none":
            parts.append(f"{'min-max' if protocol.scale == 'minmax' else 'standard'} scaled by the training part")
        return "; ".join(parts)


def adbench_split(y, seed: int, test: float = 0.3, min_rows: int | None = 1000,
                  max_rows: int | None = 10000) -> tuple[np.ndarray, np.ndarray]:
    """The rows ADBench draws for ``seed``: training and test rows, as indices into ``y``.

    ADBench's data generator (Han et al. 2022; ``DataGenerator.generator`` in
    its code) seeds numpy's global random state with the seed
    (``np.random.seed``), then

    1. bootstraps a table of fewer than ``min_rows`` rows,
       ``np.random.choice(n, min_rows, replace=True)``, or subsamples one of
       more than ``max_rows``, ``np.random.choice(n, max_rows,
       replace=False)``, seeding again first (nothing was drawn since the
       first seeding, so either way the stream starts at the seed);
    2. splits with ``train_test_split(X, y, test_size=test, shuffle=True,
       stratify=y)`` and no ``random_state``, so that scikit-learn draws from
       the same global state, where step 1 left it.

    A ``numpy.random.RandomState(seed)`` draws the same numbers as
    ``np.random.seed(seed)`` followed by ``np.random`` calls (numpy's legacy
    stream, which numpy keeps unchanged from version to version, NEP 19), and
    scikit-learn draws from it as from the global state when it is given as
    ``random_state``. So these are ADBench's rows, and numpy's global state
    is neither read nor changed.

    Parameters
    ----------
    y : array-like of shape (n_rows,)
        The table's labels, 0 normal and 1 anomaly (the split is stratified by them).
    seed : int
        The seed, in [0, 2**32) as numpy's legacy generator takes it.
    test : float, default=0.3
        The fraction of the (resized) rows tested.
    min_rows, max_rows : int or None, default=1000 and 10000
        The sizes below which the table is bootstrapped and above which it is
        subsampled (None: never).

    Returns
    -------
    train, test : ndarray of int
        Row indices into ``y``, in the order of ADBench's ``X_train`` and
        ``X_test``; a bootstrapped row may appear several times, on both sides.

    Examples
    --------
    >>> y = np.r_[np.zeros(16), np.ones(4)]
    >>> train, test = adbench_split(y, seed=1, min_rows=40)
    >>> len(train), len(test), len(set(train.tolist()) | set(test.tolist())) <= 20
    (28, 12, True)
    """
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or not 0 <= seed < 2**32:
        raise ValueError(f"resample=adbench seeds numpy's legacy generator as ADBench does: the seed must be an "
                         f"integer in [0, 2**32); got {seed!r}.")
    # imported here: the command line reads the files task and starts without scikit-learn
    from sklearn.model_selection import train_test_split

    y = np.asarray(y)
    rng = np.random.RandomState(int(seed))
    rows = _resized(rng, len(y), min_rows, max_rows)
    train, tested = train_test_split(rows, test_size=test, shuffle=True, stratify=y[rows], random_state=rng)
    return train, tested


def _resized(rng, n: int, min_rows: int | None, max_rows: int | None) -> np.ndarray:
    """Step 1: the rows of a table of ``n`` rows, bootstrapped or subsampled by ``rng`` (either numpy generator)."""
    if min_rows is not None and n < min_rows:
        return rng.choice(n, min_rows, replace=True)
    if max_rows is not None and n > max_rows:
        return rng.choice(n, max_rows, replace=False)
    return np.arange(n)


def _tag(name: str) -> int:
    """A stable number of a task's name, so that two tables of one seed draw independently."""
    return int.from_bytes(hashlib.sha256(name.encode()).digest()[:4], "little")


# ------------------------------------------------------------------ arrays in Python
@dataclass(frozen=True, eq=False)
class ResampledTask:
    """A labelled table of scans drawn into a task for each seed (:func:`resampled`)."""

    name: str
    X: np.ndarray
    y: np.ndarray
    protocol: Resampling

    def for_seed(self, seed: int) -> Dataset:
        """The task of ``seed``: split, cleaned and scaled as :attr:`protocol` says."""
        data = Dataset(self.name, self.X, y=self.y)
        task = self.protocol.apply(data, seed)
        return replace(task, metadata={**task.metadata, "task": self.name, "train_passes": 1,
                                       "split_description": self.protocol.describe()})


def resampled(X, y, name: str = "arrays", **protocol) -> ResampledTask:
    """Arrays ``X`` (scans by features) and labels ``y`` (0/1) as a task drawn for each seed.

    ``protocol`` takes the options of :class:`Resampling` (``resample``,
    ``test``, ``min_rows``, ``max_rows``, ``scale``, ``training``);
    ``resample`` is required, since arrays carry no split of their own.
    ``resampled(X, y, resample="adbench")`` (or ``**ADBENCH``) is ADBench's
    protocol, drawn as its code draws it.

    >>> import numpy as np
    >>> X, y = np.arange(40.0).reshape(20, 2), np.r_[np.zeros(16), np.ones(4)]
    >>> task = resampled(X, y, resample="stratified", test=0.5).for_seed(0)
    >>> int((task.split == "test").sum()), int(task.test().y.sum())
    (10, 2)
    """
    unknown = sorted(set(protocol) - set(OPTIONS))
    if unknown:
        raise TypeError(f"resampled() got an unknown option {unknown[0]!r}; options: {', '.join(OPTIONS)}.")
    checked = Resampling(**protocol).check()
    if not checked.draws:
        raise ValueError("resampled() needs resample='stratified', 'shuffled' or 'adbench': arrays carry no "
                         "split of their own.")
    X = np.asarray(X, dtype=np.float64)
    if X.ndim != 2:
        raise ValueError(f"X must be 2-D (scans by features); got shape {X.shape}.")
    labels = check_labels(y, f"{name}, labels")
    if labels.shape != (X.shape[0],):
        raise ValueError(f"y needs one label a scan of X: X has {X.shape[0]} rows, y {labels.size}.")
    bad = np.argwhere(~np.isfinite(X))
    if bad.size:
        i, k = bad[0]
        raise ValueError(f"{name}: X[{i}, {k}] is {X[i, k]}; scans must be finite numbers.")
    return ResampledTask(name, X, labels, checked)
