"""Loaders for two public sonar datasets, and novelty tasks on them.

The files are never fetched and never copied into the project: pass
``path=`` (the file, or a folder holding it), or set ``NOVELTY_DATA_DIR`` to
a folder holding the dataset folders (``wall-following-robot-navigation/``,
``sonar-mines-vs-rocks/``), as in the project's shared data folder.

References
----------
Freire, A., Veloso, M. & Barreto, G. (2010). Wall-Following Robot Navigation
Data. UCI Machine Learning Repository, https://doi.org/10.24432/C57C8W (CC BY 4.0).

Freire, A. L., Barreto, G. A., Veloso, M. & Varela, A. T. (2009). Short-term
memory mechanisms in neural network learning of robot navigation tasks: a
case study. Proc. 6th Latin American Robotics Symposium.

Sejnowski, T. & Gorman, R. (1988). Connectionist Bench (Sonar, Mines vs.
Rocks). UCI Machine Learning Repository, https://doi.org/10.24432/C5T01Q
(CC BY 4.0).

Gorman, R. P. & Sejnowski, T. J. (1988). Analysis of hidden units in a
layered network trained to classify sonar targets. Neural Networks, 1, 75-89.
"""

from __future__ import annotations

import numpy as np

from ..data import Dataset
from ..io.tables.data_files import read_rows, resolve_data_file

__all__ = ["uci_wall_following", "uci_wall_following_novelty", "uci_sonar", "uci_sonar_mines",
           "WALL_FOLLOWING_CLASSES"]

#: The steering commands labelling the wall-following data, in file order of first use.
WALL_FOLLOWING_CLASSES = ("Move-Forward", "Slight-Right-Turn", "Sharp-Right-Turn",
                          "Slight-Left-Turn")
_WF_FILE, _WF_FOLDER = "sensor_readings_24.data", "wall-following-robot-navigation"
_SONAR_FILE, _SONAR_FOLDER = "sonar.all-data", "sonar-mines-vs-rocks"


def _check_threshold(threshold):
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float)) or not threshold > 0:
        raise ValueError(f"threshold must be a positive number of metres; got {threshold!r}.")


def uci_wall_following(path=None, threshold: float = 5.0, normalise: bool = True):
    """The UCI Wall-Following Robot Navigation data: 5456 scans of 24 ultrasound sensors.

    A SCITOS G5 robot followed the walls of a room clockwise for four
    rounds, its 24 sensors sampled at 9 Hz; each scan is labelled with the
    controller's command (Freire et al., 2009).

    Parameters
    ----------
    path : str or Path, optional
        ``sensor_readings_24.data`` or a folder holding it (or holding
        ``wall-following-robot-navigation/``); default ``$NOVELTY_DATA_DIR``.
    threshold : float, default=5.0
        With ``normalise``, ranges become ``1 - min(r, threshold) / threshold``:
        the paper's encoding (Marsland et al., 2000) with the 5 m at which
        these sensors saturate (many readings are exactly 5.000) in place of
        the paper's 4 m. Closer is larger; everything is in [0, 1].
    normalise : bool, default=True
        False returns the ranges in metres.

    Returns
    -------
    Dataset
        ``X`` (5456, 24) in file (time) order; ``columns["class"]`` the
        command of each scan, ``metadata["class_counts"]``.
    """
    _check_threshold(threshold)
    file = resolve_data_file(path, _WF_FILE, _WF_FOLDER, "UCI Wall-Following Robot Navigation")
    ranges, classes = read_rows(file, 24, WALL_FOLLOWING_CLASSES, value_range=(0.0, 100.0))
    X = 1.0 - np.minimum(ranges, threshold) / threshold if normalise else ranges
    return Dataset(
        name="uci-wall-following",
        X=X,
        columns={"class": classes},
        metadata={
            "source": str(file),
            "class_counts": {c: int((classes == c).sum()) for c in WALL_FOLLOWING_CLASSES},
            "sensors": [f"US{i}" for i in range(1, 25)],
            "encoding": (f"1 - min(range, {threshold:g} m) / {threshold:g} m" if normalise
                         else "range (m)"),
            "sample_rate_hz": 9.0,
            "citation": "Freire, Veloso & Barreto (2010), UCI ML Repository, "
                        "doi:10.24432/C57C8W (CC BY 4.0)",
        },
    )


def uci_wall_following_novelty(path=None, train_fraction: float = 0.5, threshold: float = 5.0,
                               normal=("Move-Forward", "Slight-Right-Turn")):
    """Task: learn the scans of plain wall following, flag those that called for a turn away.

    Why this split is meaningful: the commands are a function of what the
    sensors show. Moving forward and slight right turns are what a
    clockwise wall follower does along a straight, unobstructed wall (going
    ahead, and drifting back towards the wall); they are the bulk of the
    route and the "familiar" perception. A sharp right turn or a left turn
    is needed only where the picture changes: a wall or obstacle ahead, a
    corner, the wall too close. A detector that learned only the plain
    stretches should find those scans unfamiliar, which is what a novelty
    filter on a patrolling robot is for. The split is temporal (the file is
    in time order): the first ``train_fraction`` of the recording, normal
    classes only, is the training part; the rest, every class, in order, is
    the test part, so the test is later rounds of the same room.

    Note that the novel classes are common here (about 40 % of the test
    scans), unlike the paper's rare features; report scores that do not
    depend on prevalence (e.g. ROC AUC) as well.

    Parameters
    ----------
    path : see :func:`uci_wall_following`
    train_fraction : float, default=0.5
        Share of the recording (from its start) used for training.
    threshold : float, default=5.0
        Encoding threshold (see :func:`uci_wall_following`).
    normal : tuple of str
        The familiar classes; the others are novel.
    """
    if not (isinstance(train_fraction, float) and 0.0 < train_fraction < 1.0):
        raise ValueError(f"train_fraction must be a float in (0, 1); got {train_fraction!r}.")
    normal = tuple(normal)
    unknown = [c for c in normal if c not in WALL_FOLLOWING_CLASSES]
    if unknown or not normal or len(set(normal)) == len(WALL_FOLLOWING_CLASSES):
        raise ValueError(f"normal must name some, not all, of {WALL_FOLLOWING_CLASSES}; got {normal!r}.")
    full = uci_wall_following(path, threshold)
    classes = full.columns["class"]
    cut = int(round(train_fraction * len(full)))
    is_normal = np.isin(classes, normal)
    keep = np.concatenate([np.flatnonzero(is_normal[:cut]), np.arange(cut, len(full))])
    split = np.where(keep < cut, "train", "test")
    y = np.where(split == "test", (~is_normal[keep]).astype(np.int64), 0)
    meta = dict(full.metadata)
    meta.update(normal_classes=list(normal),
                novel_classes=[c for c in WALL_FOLLOWING_CLASSES if c not in normal],
                train_fraction=train_fraction, train_passes=1, task="uci-wall-following-novelty")
    return Dataset(name="uci-wall-following-novelty", X=full.X[keep], y=y, split=split,
                   columns={"class": classes[keep], "row_index": keep}, metadata=meta)


def uci_sonar(path=None):
    """The UCI Sonar (Mines vs Rocks) data: 208 echoes, 60 band energies each in [0, 1].

    Echoes of a frequency-modulated chirp from a metal cylinder (mine, M) and
    a roughly cylindrical rock (R) at various aspect angles (Gorman &
    Sejnowski, 1988). The values are kept as they are: already in [0, 1],
    larger meaning more echo energy, the same sense as the inverted ranges.

    Returns
    -------
    Dataset
        ``X`` (208, 60) in file order (97 rocks then 111 mines);
        ``columns["class"]`` ("R"/"M") per echo.
    """
    file = resolve_data_file(path, _SONAR_FILE, _SONAR_FOLDER, "UCI Sonar (Mines vs Rocks)")
    X, classes = read_rows(file, 60, ("R", "M"), value_range=(0.0, 1.0))
    return Dataset(
        name="uci-sonar",
        X=X,
        columns={"class": classes},
        metadata={
            "source": str(file),
            "class_counts": {"R": int((classes == "R").sum()), "M": int((classes == "M").sum())},
            "encoding": "energy in each of 60 frequency bands, in [0, 1] (as published)",
            "citation": "Sejnowski & Gorman (1988), UCI ML Repository, doi:10.24432/C5T01Q "
                        "(CC BY 4.0)",
        },
    )


def uci_sonar_mines(path=None, seed: int = 0, train_fraction: float = 0.5):
    """Task: learn rock echoes, flag mine echoes as novel.

    Why this split is meaningful: in a sea-bed survey rocks are the
    background clutter, and a metal cylinder is the rare man-made object the
    survey exists to find. The two give similar, overlapping spectra
    (Gorman & Sejnowski needed a trained network to separate them, at about
    90 % accuracy), so a detector that has learned only rocks must recognise
    the mine's signature as unfamiliar without ever having seen one: a hard
    one-class problem on real sonar.

    A seeded random ``train_fraction`` of the rocks is the training part;
    the other rocks and all 111 mines, shuffled, are the test part
    (``y = 1`` for mines). The echoes are not a time series, so the order
    carries no meaning.
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative int; got {seed!r}.")
    if not (isinstance(train_fraction, float) and 0.0 < train_fraction < 1.0):
        raise ValueError(f"train_fraction must be a float in (0, 1); got {train_fraction!r}.")
    full = uci_sonar(path)
    classes = full.columns["class"]
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), 0x50A4]))
    rocks = rng.permutation(np.flatnonzero(classes == "R"))
    n_train = int(round(train_fraction * rocks.size))
    test = rng.permutation(np.concatenate([rocks[n_train:], np.flatnonzero(classes == "M")]))
    order = np.concatenate([rocks[:n_train], test])
    split = np.array(["train"] * n_train + ["test"] * test.size)
    y = np.where(split == "test", (classes[order] == "M").astype(np.int64), 0)
    meta = dict(full.metadata)
    meta.update(seed=int(seed), train_passes=1, normal_classes=["R"], novel_classes=["M"],
                task="uci-sonar-mines")
    return Dataset(name="uci-sonar-mines", X=full.X[order], y=y, split=split,
                   columns={"class": classes[order], "row_index": order}, metadata=meta)
