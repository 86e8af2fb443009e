"""Building blocks for corridors: straight walls carrying doors, cracks, boards and openings.

A corridor wall runs along ``x`` at height ``y`` of the map. ``side=-1`` is a
wall on the robot's right when it travels towards +x (things set into the
wall go to smaller ``y``); ``side=+1`` a wall on its left. Items are placed
by the x of their centre; :func:`corridor_wall` fills the wall between them.

Dimensions are approximately those of ordinary office buildings: doors
0.9 m wide, frames set 0.1-0.15 m into the wall, as in the paper's corridor
A; the deeper insets of corridors B and C are set per item.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .world import FULL_HEIGHT, MapBuilder

__all__ = ["Door", "Crack", "Board", "Opening", "Recess", "Protrusion", "Person", "corridor_wall"]

#: On-axis range (m) up to which a door frame's vertical edge is heard, approximately.
FRAME_EDGE_RANGE = 1.6
#: On-axis range (m) up to which the lips of a thin crack are heard, approximately:
#: weak enough that whether a run hears it depends on how close it passes.
CRACK_EDGE_RANGE = 0.6


@dataclass(frozen=True)
class Door:
    """A door at the back of a recess; ``open=True`` shows the room behind instead.

    ``room_depth``/``room_width`` size the office seen through an open door;
    ``box`` puts a low cardboard box in the open doorway (to stop the robot,
    as in the paper's A*, section 5.1), below the sonar beam.
    """

    id: str
    x: float
    width: float = 0.9
    depth: float = 0.12
    open: bool = False
    room_depth: float = 3.5
    room_width: float = 4.0
    box: bool = True
    frame: str = "wood"
    leaf: str = "wood"
    room: str = "plaster"
    description: str = ""
    inserted: bool = False

    def extent(self):
        return self.x - self.width / 2, self.x + self.width / 2


@dataclass(frozen=True)
class Recess:
    """A plain alcove (no door) of the wall's own material."""

    id: str
    x: float
    width: float = 1.0
    depth: float = 0.3
    description: str = ""

    def extent(self):
        return self.x - self.width / 2, self.x + self.width / 2


@dataclass(frozen=True)
class Opening:
    """A gap in the wall: a junction with a side corridor, or a missing wall panel.

    Behind the gap, walls of ``beyond`` material at ``depth`` from the wall
    line close it (a side corridor's far wall, or the cavity behind a panel).
    """

    id: str
    x: float
    width: float = 1.8
    depth: float = 6.0
    beyond: str = "breezeblock"
    kind: str = "opening"
    inserted: bool = False
    description: str = ""

    def extent(self):
        return self.x - self.width / 2, self.x + self.width / 2


@dataclass(frozen=True)
class Crack:
    """A thin vertical crack: two weak edge scatterers 1 cm apart, no geometry."""

    id: str
    x: float
    heard_to: float = CRACK_EDGE_RANGE
    description: str = "thin crack"

    def extent(self):
        return self.x, self.x


@dataclass(frozen=True)
class Board:
    """A display board fixed flat on the wall (laminated plastic by default)."""

    id: str
    x: float
    width: float = 0.9
    thickness: float = 0.03
    z: tuple = (0.6, 1.6)
    material: str = "laminate"
    inserted: bool = False
    description: str = "display board"

    def extent(self):
        return self.x - self.width / 2, self.x + self.width / 2


@dataclass(frozen=True)
class Protrusion:
    """A box-shaped object standing against the wall (a box, a bin, a cabinet)."""

    id: str
    x: float
    width: float = 0.5
    depth: float = 0.4
    height: float = 0.9
    material: str = "cardboard"
    inserted: bool = False
    description: str = "box against the wall"

    def extent(self):
        return self.x - self.width / 2, self.x + self.width / 2


@dataclass(frozen=True)
class Person:
    """A person standing ``gap`` metres from the wall: a 12-sided prism of clothing."""

    id: str
    x: float
    radius: float = 0.2
    gap: float = 0.15
    height: float = 1.75
    inserted: bool = False
    description: str = "person standing by the wall"

    def extent(self):
        return self.x - self.radius, self.x + self.radius


def _overlay(item) -> bool:
    """Items that sit on an unbroken wall rather than replace a piece of it."""
    return isinstance(item, (Crack, Board, Protrusion, Person))


def corridor_wall(b: MapBuilder, y: float, x0: float, x1: float, side: int, material: str,
                  items=(), z=FULL_HEIGHT) -> None:
    """Add a straight wall from ``x0`` to ``x1`` at ``y`` with ``items`` set into or onto it."""
    if side not in (-1, 1):
        raise ValueError("side must be -1 (right-hand wall) or +1 (left-hand wall).")
    cuts = sorted((it for it in items if not _overlay(it)), key=lambda it: it.x)
    cursor = x0
    for it in cuts:
        a, c = it.extent()
        if a < cursor - 1e-9 or c > x1:
            raise ValueError(f"Item {it.id!r} at x={it.x} overlaps another item or the wall's end.")
        b.wall((cursor, y), (a, y), material, z=z)
        _cut_item(b, it, y, side, material)
        cursor = c
    b.wall((cursor, y), (x1, y), material, z=z)
    for it in items:
        if _overlay(it):
            _overlay_item(b, it, y, side)


def _label_side(side: int) -> str:
    return "right" if side < 0 else "left"


def _cut_item(b: MapBuilder, it, y: float, side: int, material: str) -> None:
    a, c = it.extent()
    s = side
    if isinstance(it, Door):
        back = y + s * it.depth
        kind = "opening" if it.open else "door"
        fid = b.feature(it.id, kind, (it.x, y), _label_side(s), it.depth, it.width,
                        it.description or ("open door" if it.open else "door in a recess"),
                        inserted=it.inserted)
        frame = fid
        if it.open:
            # the frame is there whether the door is open or shut: opening the
            # door changes only what lies beyond it, so the frame is its own feature
            frame = b.feature(f"{it.id}-frame", "door", (it.x, y), _label_side(s), it.depth,
                              it.width, "frame of an open door")
        b.wall((a, y), (a, back), it.frame, frame)
        b.wall((c, y), (c, back), it.frame, frame)
        b.edge((a, y), FRAME_EDGE_RANGE, frame)
        b.edge((c, y), FRAME_EDGE_RANGE, frame)
        if not it.open:
            b.wall((a, back), (c, back), it.leaf, fid)
            return
        # the doorway seen from the corridor: an aperture (ground truth only),
        # the office behind, and the leaf swung open against the office wall
        b.wall((a, y), (c, y), "aperture", fid, stands_for=material)
        half = it.room_width / 2
        far = back + s * it.room_depth
        b.wall((it.x - half, back), (a, back), it.room, fid)
        b.wall((c, back), (it.x + half, back), it.room, fid)
        b.polyline([(it.x - half, back), (it.x - half, far), (it.x + half, far),
                    (it.x + half, back)], it.room, fid)
        b.wall((a, back), (a, back + s * it.width), it.leaf, fid)
        if it.box:
            # a cardboard box 0.4 m tall: the infra-red band sees it, the sonar beam passes over it
            bz = (0.0, 0.4)
            b.polyline([(a + 0.05, y + s * 0.02), (c - 0.05, y + s * 0.02),
                        (c - 0.05, y + s * 0.37), (a + 0.05, y + s * 0.37)], "cardboard",
                       fid, z=bz, closed=True)
    elif isinstance(it, Recess):
        back = y + s * it.depth
        fid = b.feature(it.id, "recess", (it.x, y), _label_side(s), it.depth, it.width,
                        it.description or "recess")
        b.polyline([(a, y), (a, back), (c, back), (c, y)], material, fid)
        b.edge((a, y), FRAME_EDGE_RANGE, fid)
        b.edge((c, y), FRAME_EDGE_RANGE, fid)
    elif isinstance(it, Opening):
        fid = b.feature(it.id, it.kind, (it.x, y), _label_side(s), it.depth, it.width,
                        it.description or "opening", inserted=it.inserted)
        back = y + s * it.depth
        b.wall((a, y), (c, y), "aperture", fid, stands_for=material)
        b.polyline([(a, y), (a, back), (c, back), (c, y)], it.beyond, fid)
        b.edge((a, y), FRAME_EDGE_RANGE, fid)
        b.edge((c, y), FRAME_EDGE_RANGE, fid)
    else:
        raise TypeError(f"Cannot cut a {type(it).__name__} into a wall.")


def _overlay_item(b: MapBuilder, it, y: float, side: int) -> None:
    s = side
    a, c = it.extent()
    if isinstance(it, Crack):
        fid = b.feature(it.id, "crack", (it.x, y), _label_side(s), 0.02, 0.01, it.description)
        b.edge((it.x - 0.005, y), it.heard_to, fid)
        b.edge((it.x + 0.005, y), it.heard_to, fid)
    elif isinstance(it, Board):
        fid = b.feature(it.id, "board", (it.x, y), _label_side(s), -it.thickness, it.width,
                        it.description, inserted=it.inserted)
        face = y - s * it.thickness
        b.polyline([(a, y), (a, face), (c, face), (c, y)], it.material, fid, z=it.z)
        b.edge((a, face), FRAME_EDGE_RANGE * 0.6, fid, z=it.z)
        b.edge((c, face), FRAME_EDGE_RANGE * 0.6, fid, z=it.z)
    elif isinstance(it, Person):
        centre_y = y - s * (it.gap + it.radius)
        fid = b.feature(it.id, "object", (it.x, centre_y), _label_side(s),
                        -(it.gap + 2 * it.radius), 2 * it.radius, it.description,
                        inserted=it.inserted)
        ang = np.linspace(0.0, 2.0 * np.pi, 13)[:-1]
        b.polyline(np.stack([it.x + it.radius * np.cos(ang), centre_y + it.radius * np.sin(ang)],
                            axis=1), "fabric", fid, z=(0.0, it.height), closed=True)
    elif isinstance(it, Protrusion):
        fid = b.feature(it.id, "object", (it.x, y - s * it.depth / 2), _label_side(s), -it.depth,
                        it.width, it.description, inserted=it.inserted)
        face = y - s * it.depth
        z = (0.0, it.height)
        b.polyline([(a, y), (a, face), (c, face), (c, y)], it.material, fid, z=z)
        b.edge((a, face), FRAME_EDGE_RANGE, fid, z=z)
        b.edge((c, face), FRAME_EDGE_RANGE, fid, z=z)
