"""Maps: wall segments with materials, edge scatterers, and named features.

A :class:`WorldMap` is what the sonar and the wall-follower see: straight
segments (each with a material, a vertical extent and, optionally, the map
feature it belongs to) and point *edges* (the vertical edges of door frames,
the lips of a crack), which return a weak echo from any direction
(Kuc & Siegel, 1987, model edges this way). Maps are built with
:class:`MapBuilder` and never change afterwards, so one map can be shared by
many runs.

Coordinates are metres; angles radians, counter-clockwise from +x.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .materials import MATERIALS, get_material

__all__ = ["Feature", "WorldMap", "MapBuilder", "FULL_HEIGHT"]

#: Vertical extent (m) of floor-to-ceiling walls.
FULL_HEIGHT = (0.0, 2.6)

FEATURE_KINDS = ("door", "crack", "board", "recess", "opening", "object")


@dataclass(frozen=True)
class Feature:
    """A named thing in a map, for ground truth and figures.

    Attributes
    ----------
    id : str
        Unique within the map (``"door-3"``, ``"crack-1"``).
    kind : str
        One of ``"door"``, ``"crack"``, ``"board"``, ``"recess"``,
        ``"opening"``, ``"object"``.
    centre : tuple of float
        (x, y) of the feature's middle.
    side : str
        ``"right"``, ``"left"`` or ``"none"``, seen from the direction of travel.
    depth : float
        How far it is set into (positive) or stands out of (negative) the wall.
    width : float
        Its extent along the wall (m).
    description : str
        A short human description.
    inserted : bool
        True for novelties added to a clean map (inspection tasks).
    """

    id: str
    kind: str
    centre: tuple
    side: str = "none"
    depth: float = 0.0
    width: float = 0.0
    description: str = ""
    inserted: bool = False


@dataclass(frozen=True, eq=False)
class WorldMap:
    """Immutable geometry of one environment.

    Attributes
    ----------
    p0, p1 : ndarray of shape (n_segments, 2)
        Segment end points.
    material : ndarray of shape (n_segments,) of int
        Index into :attr:`materials`.
    z : ndarray of shape (n_segments, 2)
        Lowest and highest point (m) of each segment above the floor.
    feature : ndarray of shape (n_segments,) of int
        Index into :attr:`features`, or -1 for plain wall.
    stands_for : ndarray of shape (n_segments,) of int
        For an ``"aperture"`` (an opening, transparent to sound): index into
        :attr:`materials` of the surface it replaces, used to decide whether
        a sonar noticed the opening; -1 elsewhere.
    edges : ndarray of shape (n_edges, 2)
        Positions of the edge scatterers.
    edge_range : ndarray of shape (n_edges,)
        Range (m) up to which each edge is heard on the beam axis.
    edge_z : ndarray of shape (n_edges, 2)
        Vertical extent of each edge.
    edge_feature : ndarray of shape (n_edges,) of int
        Feature index of each edge, or -1.
    materials : tuple of Material
        The materials used, indexed by :attr:`material`.
    features : tuple of Feature
        The named features.
    """

    p0: np.ndarray
    p1: np.ndarray
    material: np.ndarray
    z: np.ndarray
    feature: np.ndarray
    stands_for: np.ndarray
    edges: np.ndarray
    edge_range: np.ndarray
    edge_z: np.ndarray
    edge_feature: np.ndarray
    materials: tuple
    features: tuple

    @property
    def n_segments(self) -> int:
        return self.p0.shape[0]

    def material_table(self) -> dict[str, np.ndarray]:
        """Per-segment material properties as arrays (reflectivity, lobe in radians, specular)."""
        mats = self.materials
        take = lambda attr: np.array([getattr(m, attr) for m in mats], dtype=np.float64)[self.material]  # noqa: E731
        return {
            "reflectivity": take("reflectivity"),
            "lobe": np.radians(take("lobe")),
            "specular": take("specular"),
            "transparent": take("reflectivity") <= 0.0,
        }

    def feature_index(self, feature_id: str) -> int:
        for i, f in enumerate(self.features):
            if f.id == feature_id:
                return i
        raise KeyError(f"No feature {feature_id!r} in this map; it has "
                       f"{', '.join(f.id for f in self.features) or '(none)'}.")

    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of every segment."""
        pts = np.vstack([self.p0, self.p1])
        return (*pts.min(axis=0), *pts.max(axis=0))


@dataclass
class MapBuilder:
    """Collects segments, edges and features, then freezes them into a :class:`WorldMap`.

    Examples
    --------
    >>> b = MapBuilder()
    >>> b.wall((0, 0), (5, 0), "breezeblock")
    >>> fid = b.feature("crack-1", "crack", centre=(2.0, 0.0), side="right")
    >>> b.edge((2.0, 0.0), heard_to=1.0, feature=fid)
    >>> m = b.build()
    >>> m.n_segments, m.edges.shape, m.features[0].id
    (1, (1, 2), 'crack-1')
    """

    _segments: list = field(default_factory=list)
    _edges: list = field(default_factory=list)
    _features: list = field(default_factory=list)

    def feature(self, id: str, kind: str, centre, side="none", depth=0.0, width=0.0,
                description="", inserted=False) -> str:
        """Declare a feature; returns its id, to pass to :meth:`wall` and :meth:`edge`."""
        if kind not in FEATURE_KINDS:
            raise ValueError(f"Unknown feature kind {kind!r}; expected one of {FEATURE_KINDS}.")
        if any(f.id == id for f in self._features):
            raise ValueError(f"Feature id {id!r} is used twice.")
        self._features.append(Feature(id, kind, (float(centre[0]), float(centre[1])), side,
                                      float(depth), float(width), description, inserted))
        return id

    def wall(self, p0, p1, material: str, feature: str | None = None, z=FULL_HEIGHT,
             stands_for: str | None = None) -> None:
        """Add one straight segment from ``p0`` to ``p1``.

        ``stands_for`` names, for an ``"aperture"``, the material of the
        surface the opening replaces.
        """
        get_material(material)
        if stands_for is not None:
            get_material(stands_for)
        if np.allclose(p0, p1):
            return  # zero-length pieces arise naturally when items touch
        self._segments.append((tuple(map(float, p0)), tuple(map(float, p1)), material, tuple(z),
                               feature, stands_for))

    def polyline(self, points, material: str, feature: str | None = None, z=FULL_HEIGHT,
                 closed=False) -> None:
        """Add segments joining consecutive ``points`` (and the last to the first if ``closed``)."""
        pts = [tuple(p) for p in points]
        if closed:
            pts.append(pts[0])
        for a, b in zip(pts[:-1], pts[1:]):
            self.wall(a, b, material, feature, z)

    def edge(self, p, heard_to: float, feature: str | None = None, z=FULL_HEIGHT) -> None:
        """Add an edge scatterer at ``p`` heard on axis up to ``heard_to`` metres."""
        self._edges.append((tuple(map(float, p)), float(heard_to), tuple(z), feature))

    def build(self) -> WorldMap:
        ids = [f.id for f in self._features]
        used = [s[4] for s in self._segments] + [e[3] for e in self._edges]
        for fid in used:
            if fid is not None and fid not in ids:
                raise ValueError(f"Feature {fid!r} is used but was never declared.")
        names = sorted({s[2] for s in self._segments} | {s[5] for s in self._segments if s[5]})
        names = names or ["breezeblock"]
        index = {n: i for i, n in enumerate(names)}
        fidx = lambda fid: -1 if fid is None else ids.index(fid)  # noqa: E731
        seg = self._segments
        edges = self._edges
        return WorldMap(
            p0=np.array([s[0] for s in seg], dtype=np.float64).reshape(-1, 2),
            p1=np.array([s[1] for s in seg], dtype=np.float64).reshape(-1, 2),
            material=np.array([index[s[2]] for s in seg], dtype=np.intp),
            z=np.array([s[3] for s in seg], dtype=np.float64).reshape(-1, 2),
            feature=np.array([fidx(s[4]) for s in seg], dtype=np.intp),
            stands_for=np.array([index[s[5]] if s[5] else -1 for s in seg], dtype=np.intp),
            edges=np.array([e[0] for e in edges], dtype=np.float64).reshape(-1, 2),
            edge_range=np.array([e[1] for e in edges], dtype=np.float64),
            edge_z=np.array([e[2] for e in edges], dtype=np.float64).reshape(-1, 2),
            edge_feature=np.array([fidx(e[3]) for e in edges], dtype=np.intp),
            materials=tuple(MATERIALS[n] for n in names),
            features=tuple(self._features),
        )
