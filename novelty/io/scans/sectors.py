"""A laser scan's beams cut into sectors, and each sector's beams reduced to one range.

The paper's novelty filter takes a ring of ranges, one a sensor around the
robot (16 sonars, Marsland et al. 2000, section 4.1); a laser scan holds
hundreds of beams. :func:`sector_index` cuts the beams' angles, measured
from the robot's ``front``, into ``n_sectors`` equal sectors between the
angular ``limits``, ordered counter-clockwise (for a front laser: from the
robot's right to its left; a scan all round starts at the robot's front,
whatever angle its driver starts at), and :func:`reduce_sectors` reduces
each sector's valid beams (cleaned by :func:`novelty.io.scans.ranges.clean_ranges`)
to one range: their minimum (what a sonar's cone reports: its nearest echo,
the paper's sensor), their mean, their median or a percentile. A sector
with no valid beam reads ``+inf`` (nothing seen). By default each beam
owns an equal slice of the scan's span, so ``n_sectors`` equal to the
number of beams gives the beams back unchanged.

``clip`` (m) counts every range beyond it, ``+inf`` included, as ``clip``
before reducing: with ``clip`` the paper's threshold, a sector's mean then
preprocesses to the mean of its beams' preprocessed values (the
preprocessing is linear below the threshold), where without it one beam
without an echo makes the whole sector's mean ``+inf``.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features
of an environment using habituation. Proc. SAB 2000, section 4.1.
"""

from __future__ import annotations

import math
import numbers
import warnings

import numpy as np

__all__ = ["sector_index", "scan_limits", "all_round", "reduce_sectors", "REDUCTIONS", "SNAP"]

#: Angles (rad) this close below a sector's boundary count in the sector beyond it: a message's float32
#: angles are exact to about 4e-7 rad near pi.
SNAP = 1e-6
#: Named ways to reduce a sector's beams to one range (a number q is the q-th percentile).
REDUCTIONS = ("min", "mean", "median")


def sector_index(angles, n_sectors: int, limits: tuple[float, float] | None = None,
                 front: float = 0.0) -> np.ndarray:
    """The sector of every beam (-1 outside the limits), sectors counter-clockwise from ``limits[0]``.

    Parameters
    ----------
    angles : array-like of shape (n_beams,)
        The beams' angles (rad), evenly spaced and increasing, in the frame
        in which the robot's front is at ``front``.
    n_sectors : int
    limits : (float, float), optional
        The angular span (rad, from the front, ``low < high``) cut into
        sectors; a beam's angle counts within the turn from ``low``. Default:
        the scan's span, each beam owning an equal slice of it (half a beam's
        spacing beyond the first and last beams), so the ring starts at the
        first beam; a scan all round (:func:`all_round`) starts at the front:
        ``(0, 2 pi)``.
    front : float, default=0.0
        The angle (rad) of the robot's front in the scan's frame.

    Examples
    --------
    >>> angles = np.deg2rad([-90, -45, 0, 45, 90])
    >>> sector_index(angles, 5).tolist(), sector_index(angles, 2).tolist()
    ([0, 1, 2, 3, 4], [0, 0, 1, 1, 1])
    >>> sector_index(angles, 2, limits=(-np.pi / 4, np.pi / 4)).tolist()
    [-1, 0, 1, 1, -1]
    """
    if isinstance(n_sectors, bool) or not isinstance(n_sectors, numbers.Integral) or n_sectors < 1:
        raise ValueError(f"n_sectors must be an int >= 1; got {n_sectors!r}.")
    a = np.asarray(angles, dtype=np.float64) - front
    if limits is None and all_round(a):
        low, high = 0.0, 2 * math.pi
        a = np.mod(a, 2 * math.pi)
    elif limits is None:
        a, low, high = _span(a)
    else:
        low, high = _checked_limits(limits)
        a = low + np.mod(a - low, 2 * math.pi)     # each beam's angle within the turn from low
    k = _sectors_within(a, low, high, n_sectors)
    empty = sorted(set(range(n_sectors)) - set(k.tolist()))
    if empty:
        raise ValueError(f"{len(empty)} of {n_sectors} sectors hold no beam (sectors {empty[:5]}...): "
                         f"{len(a)} beams cannot fill them; use fewer sectors or wider limits.")
    return k


def scan_limits(angles, front: float = 0.0) -> tuple[float, float]:
    """The limits :func:`sector_index` takes by default: the scan's span from the front (rad).

    Examples
    --------
    >>> [round(float(np.rad2deg(v)), 1) for v in scan_limits(np.deg2rad([-90, -45, 0, 45, 90]))]
    [-112.5, 112.5]
    """
    a = np.asarray(angles, dtype=np.float64) - front
    if all_round(a):
        return 0.0, 2 * math.pi
    _, low, high = _span(a)
    return low, high


def all_round(angles) -> bool:
    """Whether the beams look all round: at least 32, no gap between neighbours wider than twice the usual one.

    A scan all round (a 360-degree lidar, fragments of a whole revolution,
    sensors merged) has its ring start at the robot's front, whatever angle
    its driver starts at. A scan of fewer beams keeps its first beam's
    start: a few coarse beams do not tell a turn from a turn with a hole, and
    sectors counted from the front need not meet them.

    Examples
    --------
    >>> all_round(np.deg2rad(np.arange(-180, 180))), all_round(np.deg2rad(np.arange(0, 359)))
    (True, True)
    >>> all_round(np.deg2rad(np.arange(-135, 135))), all_round(np.deg2rad([0, 90, 180, 270]))
    (False, False)
    """
    a = np.sort(np.mod(np.asarray(angles, dtype=np.float64), 2 * math.pi))
    if len(a) < 32:
        return False
    gaps = np.diff(np.concatenate([a, [a[0] + 2 * math.pi]]))
    return bool(gaps.max() <= 2 * np.median(gaps))


def _span(a: np.ndarray) -> tuple[np.ndarray, float, float]:
    # the scan kept in one piece, turned by whole turns so that its middle is within half a
    # turn of the front (a rear laser's beams, 90..270 degrees, cross +-180 and stay together)
    centre = (float(a.min()) + float(a.max())) / 2
    a = a + ((centre + math.pi) % (2 * math.pi) - math.pi - centre)
    half = abs(float(np.median(np.diff(a)))) / 2 if len(a) > 1 else math.pi
    return a, float(a.min()) - half, float(a.max()) + half


def _checked_limits(limits) -> tuple[float, float]:
    low, high = (float(v) for v in limits)
    if not (-2 * math.pi <= low < high <= 2 * math.pi):
        raise ValueError(f"limits must be (low, high) radians with low < high; got {limits!r}.")
    return low, high


def _sectors_within(a: np.ndarray, low: float, high: float, n_sectors: int) -> np.ndarray:
    """Each angle's sector of [low, high] cut in ``n_sectors`` (-1 beyond either limit).

    A beam within :data:`SNAP` below a sector's first angle counts in that
    sector: a beam on a boundary (a 0.5-degree lidar's every 45th, cut in 16
    sectors) falls on the same side whatever the float32 rounding of its
    driver's first angle and spacing.
    """
    if high - low >= 2 * math.pi - 1e-12:   # a whole turn: its high end is its low end, where sector 0 begins
        a = np.where(a >= high - SNAP, low, a)
    k = np.floor((a - low + SNAP) / (high - low) * n_sectors).astype(np.intp)
    # a beam on the high limit belongs to the last sector; beyond either limit to none (np.isclose's
    # test with its defaults, written out: its wrapper costs more than the scan)
    k = np.where(np.abs(a - high) <= 1e-8 + 1e-5 * abs(high), n_sectors - 1, k)
    return np.where((a < low - 1e-12) | (a > high + 1e-12) | (k < 0) | (k >= n_sectors), -1, k)


def reduce_sectors(ranges, index: np.ndarray, n_sectors: int, reduce="min",
                   clip: float | None = None) -> np.ndarray:
    """Reduce each sector's valid beams (not NaN) to one range; ``+inf`` where a sector has none.

    Parameters
    ----------
    ranges : array-like of shape (n_beams,) or (n_scans, n_beams)
        Cleaned ranges (:func:`clean_ranges`).
    index : ndarray of shape (n_beams,)
        Each beam's sector (:func:`sector_index`); -1 beams are left out.
    n_sectors : int
    reduce : {"min", "mean", "median"} or float, default="min"
        A number ``q`` in [0, 100] takes the q-th percentile (linear).
    clip : float, optional
        Ranges beyond ``clip`` (m) count as ``clip``.

    Examples
    --------
    >>> r = [1.0, 3.0, np.nan, 2.0, np.inf, 4.0]
    >>> idx = np.array([0, 0, 0, 1, 1, 1])
    >>> reduce_sectors(r, idx, 2).tolist(), reduce_sectors(r, idx, 2, "mean").tolist()
    ([1.0, 2.0], [2.0, inf])
    >>> reduce_sectors(r, idx, 2, "mean", clip=4.0).tolist(), reduce_sectors(r, idx, 2, 50).tolist()
    ([2.0, 3.3333333333333335], [2.0, 4.0])
    """
    _check_reduce(reduce)
    r = np.asarray(ranges, dtype=np.float64)
    one = r.ndim == 1
    r = np.atleast_2d(r)
    if clip is not None:
        r = np.where(r > clip, clip, r)   # NaN stays NaN
    out = np.empty((r.shape[0], n_sectors))
    for k in range(n_sectors):
        out[:, k] = _reduce(r[:, index == k], reduce)
    return out[0] if one else out


def _reduce(block: np.ndarray, reduce) -> np.ndarray:
    valid = ~np.isnan(block)
    count = valid.sum(axis=1)
    if reduce == "min":
        value = np.where(valid, block, np.inf).min(axis=1, initial=np.inf)   # a sector may hold no beam
    elif reduce == "mean":
        with np.errstate(invalid="ignore"):
            value = np.where(valid, block, 0.0).sum(axis=1) / np.maximum(count, 1)
    else:
        q = 50.0 if reduce == "median" else float(reduce)
        # linear interpolation towards +inf is +inf (numpy's gives NaN): interpolate with a
        # finite stand-in, then anything beyond the sector's largest finite range is +inf
        stand_in = np.where(np.isposinf(block), 1e300, block)
        largest = np.where(np.isfinite(block), block, -np.inf).max(axis=1, initial=-np.inf)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)   # all-NaN sectors: answered below
            value = np.nanpercentile(stand_in, q, axis=1) if block.shape[1] else np.full(len(block), np.nan)
        value = np.where(value > largest, np.inf, value)
    return np.where(count > 0, value, np.inf)


def _check_reduce(reduce) -> None:
    if reduce in REDUCTIONS:
        return
    if isinstance(reduce, numbers.Real) and not isinstance(reduce, bool) and 0 <= reduce <= 100:
        return
    raise ValueError(f"reduce must be one of {', '.join(REDUCTIONS)} or a percentile in [0, 100]; "
                     f"got {reduce!r}.")
