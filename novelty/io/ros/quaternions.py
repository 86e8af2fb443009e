"""Rotations as unit quaternions ``(x, y, z, w)``, tf's order: products, rotation of vectors, interpolation.

A quaternion ``q = (x, y, z, w)`` rotates a vector ``v`` to ``q v q*``; the
product ``a * b`` rotates by ``b`` first, then by ``a`` (Hamilton's
convention, as tf2 and Eigen use it). ``yaw`` is the rotation about z of
the ZYX Euler angles (REP 103's heading).

References
----------
Shoemake, K. (1985). Animating rotation with quaternion curves. SIGGRAPH
'85 (slerp). REP 103, "Standard Units of Measure and Coordinate Conventions".
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["yaw", "multiply", "conjugate", "rotate", "slerp", "normalized", "matrix", "IDENTITY"]

IDENTITY = (0.0, 0.0, 0.0, 1.0)


def yaw(q) -> float:
    """The heading of ``q``: its rotation about z (ZYX Euler angles' yaw)."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def normalized(q) -> tuple[float, float, float, float]:
    """``q`` scaled to unit length; ValueError for a zero or non-finite quaternion."""
    n = math.sqrt(sum(v * v for v in q))
    if not (math.isfinite(n) and n > 1e-12):
        raise ValueError(f"{tuple(q)} is not a rotation (a quaternion of length {n}).")
    return tuple(v / n for v in q)


def multiply(a, b) -> tuple[float, float, float, float]:
    """The rotation ``b`` then ``a``: the Hamilton product ``a * b``.

    Examples
    --------
    >>> quarter = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))   # 90 degrees about z
    >>> [round(v, 6) for v in multiply(quarter, quarter)]                      # 180 degrees
    [0.0, 0.0, 1.0, 0.0]
    """
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def conjugate(q) -> tuple[float, float, float, float]:
    """The inverse rotation of a unit quaternion."""
    x, y, z, w = q
    return (-x, -y, -z, w)


def matrix(q) -> np.ndarray:
    """The 3 x 3 rotation matrix of a unit quaternion."""
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rotate(q, v) -> tuple[float, float, float]:
    """The vector ``v`` rotated by ``q``.

    Examples
    --------
    >>> flipped = (1.0, 0.0, 0.0, 0.0)               # 180 degrees about x: upside down
    >>> [round(c, 6) + 0.0 for c in rotate(flipped, (0.0, 1.0, 0.0))]   # y (left) becomes -y (right)
    [0.0, -1.0, 0.0]
    """
    # v + 2 w (q x v) + 2 q x (q x v), with q's vector part (x, y, z): no matrix made
    qx, qy, qz, qw = q
    vx, vy, vz = v
    tx, ty, tz = 2 * (qy * vz - qz * vy), 2 * (qz * vx - qx * vz), 2 * (qx * vy - qy * vx)
    return (vx + qw * tx + qy * tz - qz * ty, vy + qw * ty + qz * tx - qx * tz, vz + qw * tz + qx * ty - qy * tx)


def slerp(a, b, t: float) -> tuple[float, float, float, float]:
    """The rotation a fraction ``t`` of the way from ``a`` to ``b`` along the shorter arc (Shoemake 1985)."""
    dot = sum(p * q for p, q in zip(a, b))
    if dot < 0:   # q and -q are one rotation: take the shorter way
        b, dot = tuple(-v for v in b), -dot
    if dot > 1 - 1e-10:   # equal to 1e-5 rad: the chord is the arc (and sin(theta) too small to divide by)
        return normalized(tuple(p + t * (q - p) for p, q in zip(a, b)))
    theta = math.acos(min(dot, 1.0))
    s = math.sin(theta)
    wa, wb = math.sin((1 - t) * theta) / s, math.sin(t * theta) / s
    return tuple(wa * p + wb * q for p, q in zip(a, b))
