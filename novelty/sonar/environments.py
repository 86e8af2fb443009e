"""The paper's environments as maps: corridors A, A*, B, C and the open control area.

Marsland et al. (2000, section 4.3 and figure 3) used two sections of
corridor on the second floor of the Computer Science building in
Manchester (A and B: 1.7 m wide, painted breezeblock walls, varnished wooden
doors into offices), one on the first floor (C: 2.1 m wide, smooth brick on
one side and glass on the other, low display boards of laminated, shiny
plastic), and a large open area for control training. The robot followed
the right-hand wall for 10 m in each.

What the paper states is kept; what it leaves open (positions of most
doors, recess depths, the rooms behind) is chosen here, approximately, and
marked "chosen". The maps are built so that the paper's comparisons follow
from geometry, not from tuning:

- A: doors set 0.12 m into the walls (chosen), a thin crack near the start
  (stated), a door on the right at about 3 m (stated), and further office
  doors on both sides (chosen; :func:`corridor_a` can leave them out).
- A*: A with that door open; a low cardboard box in the doorway stopped the
  robot but "did not appear on the sonar scans" (stated), so the doorway
  reads as a deep opening into an office.
- B: the same construction; two doors on the right, the first ("door G")
  "inset deeper than those in the first corridor" (stated; 0.35 m chosen);
  notice boards above the sonars' height (stated; invisible here too).
- C: 2.1 m wide, smooth brick on the followed (right) side and glass on the
  other (which side is which is chosen: the robot followed the brick with
  infra-red), a "particularly deeply inset" doorway (0.9 m chosen), low
  display boards near the end, a crack at about 7 m (stated); the glass is
  held by metal glazing bars every 1.2 m (chosen).
- control: a 16 m x 10 m hall; the route runs 1.8 m along a wall, turns into
  the middle (about 3 m out), comes back and follows the wall again (stated
  in outline).

The route starts at x = 0 and runs towards +x; the right-hand wall is
``y = 0``. Every corridor extends 6 m beyond both ends of the route so that
its ends are beyond the sonar's reach from the route.

References
----------
Marsland, S., Nehmzow, U. & Shapiro, J. (2000). Detecting novel features of
an environment using habituation. Proc. SAB 2000, sections 4.3 and 5.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np

from .controller import WallFollower, WaypointFollower
from .layout import FRAME_EDGE_RANGE, Board, Crack, Door, corridor_wall
from .world import MapBuilder, WorldMap

__all__ = ["Environment", "get_environment", "environment_names", "corridor_environment",
           "corridor_a", "ROUTE_LENGTH"]

#: Length (m) of every paper route (Marsland et al., 2000, section 4.2).
ROUTE_LENGTH = 10.0
_MARGIN = 6.0


@dataclass(frozen=True, eq=False)
class Environment:
    """A map, how the robot drives through it, and where its features are.

    Attributes
    ----------
    name : str
        Short name (``"a"``, ``"a-star"``, ``"b"``, ``"c"``, ``"control"``, or a
        generated corridor's name).
    world : WorldMap
    controller : WallFollower or WaypointFollower
    start : tuple of float
        Nominal starting pose (x, y, heading).
    route : ndarray of shape (k, 2)
        The nominal course, used to place features along the route.
    length : float
        Metres driven per run.
    description : str
    """

    name: str
    world: WorldMap
    controller: Any
    start: tuple
    route: np.ndarray
    length: float = ROUTE_LENGTH
    description: str = ""

    def position_of(self, point) -> float:
        """Distance along the nominal route (m) of the point of it nearest ``point``."""
        path = self.route
        a, b = path[:-1], path[1:]
        ab = b - a
        p = np.asarray(point, dtype=np.float64)
        u = np.sum((p - a) * ab, axis=1) / np.sum(ab * ab, axis=1)
        # the route's first and last legs extend beyond its ends, so a feature
        # past either end gets a position outside [0, length]
        low = np.zeros_like(u)
        high = np.ones_like(u)
        low[0], high[-1] = -np.inf, np.inf
        u = np.clip(u, low, high)
        d = np.linalg.norm(a + u[:, None] * ab - p, axis=1)
        k = int(np.argmin(d))
        seg_len = np.linalg.norm(ab, axis=1)
        return float(seg_len[:k].sum() + u[k] * seg_len[k])

    def feature_table(self) -> list[dict]:
        """One record per map feature: id, kind, position along the route (m), side, depth, width."""
        rows = []
        for f in self.world.features:
            rows.append({
                "id": f.id,
                "kind": f.kind,
                "position": round(self.position_of(f.centre), 3),
                "side": f.side,
                "depth": f.depth,
                "width": f.width,
                "inserted": f.inserted,
                "description": f.description,
            })
        return sorted(rows, key=lambda r: (r["position"], r["id"]))


def corridor_environment(name: str, width: float, right: str, left: str, right_items=(),
                         left_items=(), description: str = "",
                         follower: WallFollower | None = None,
                         length: float = ROUTE_LENGTH, extra=None) -> Environment:
    """A straight corridor ``width`` wide, the robot following its right-hand wall.

    ``right``/``left`` are the wall materials; the items are
    :mod:`~novelty.sonar.layout` objects placed along each wall. ``extra``,
    if given, is called with the :class:`MapBuilder` to add anything else.
    """
    follower = follower or WallFollower()
    b = MapBuilder()
    x0, x1 = -_MARGIN, length + _MARGIN
    corridor_wall(b, 0.0, x0, x1, -1, right, right_items)
    corridor_wall(b, width, x0, x1, +1, left, left_items)
    # the corridor's ends, out of reach from the route but closing the map
    b.wall((x0, 0.0), (x0, width), "breezeblock")
    b.wall((x1, 0.0), (x1, width), "breezeblock")
    if extra is not None:
        extra(b)
    d = follower.distance
    return Environment(name, b.build(), follower, (0.0, d, 0.0),
                       np.array([[0.0, d], [length + 1.0, d]]), length, description)


# ------------------------------------------------------------------ the maps
def _left_doors_ab():
    return [Door("door-l1", 1.6), Door("door-l2", 5.2), Door("door-l3", 9.1),
            Door("door-l0", -2.0), Door("door-l4", 13.0)]


def corridor_a(open_door: bool = False, extra_doors: bool = True) -> Environment:
    """Corridor A (or A* with ``open_door``), with or without the doors the paper does not name.

    The paper names two features of A: a thin crack near the start and a
    door on the right at about 3 m (section 4.1, figure 4). It also says
    that doors lead from the corridors into offices, without saying where,
    so the map adds ``extra_doors`` (chosen): a second door on the right at
    7.6 m, three on the left (1.6, 5.2 and 9.1 m) and one beyond each end
    of the route on each side, as in an office corridor. They are
    perceptions the paper's runs may not have had; ``extra_doors=False``
    leaves only the two named features (see docs/reproduction.md for what
    they change).
    """
    door = Door("door-r1-open" if open_door else "door-r1", 3.0, open=open_door,
                description="door on the right at about 3 m" + (", opened" if open_door else ""))
    right = [Crack("crack-1", 0.8, description="thin crack near the start"), door]
    left = []
    if extra_doors:
        right += [Door("door-r2", 7.6), Door("door-r0", -2.6), Door("door-r3", 12.4)]
        left = _left_doors_ab()
    if open_door:
        desc = ("Corridor A* (Marsland et al. 2000): A with the door on the right at 3 m open; "
                "a low box in the doorway is below the sonar beam.")
    else:
        desc = ("Corridor A (Marsland et al. 2000): 1.7 m wide, painted breezeblock, varnished "
                "wooden doors in shallow recesses, a thin crack near the start.")
    name = "a-star" if open_door else "a"
    if not extra_doors:
        name += "-named"
        desc += " Only the features the paper names: the crack and the door on the right."
    return corridor_environment(name, 1.7, "breezeblock", "breezeblock", right, left, desc)


def _build_b() -> Environment:
    right = [Door("door-g", 3.6, depth=0.35, description="door G: inset deeper than any door in A"),
             Door("door-r2", 7.8), Door("door-r0", -2.2), Door("door-r3", 12.6)]
    left = [Door("door-l1", 1.0), Door("door-l2", 4.8), Door("door-l3", 8.6),
            Door("door-l0", -2.8), Door("door-l4", 12.2),
            Board("notice-1", 6.2, width=1.2, thickness=0.02, z=(1.3, 2.1), material="wood",
                  description="notice board above the sonars"),
            Board("notice-2", 7.4, width=0.9, thickness=0.02, z=(1.3, 2.1), material="wood",
                  description="notice board above the sonars")]
    return corridor_environment(
        "b", 1.7, "breezeblock", "breezeblock", right, left,
        "Corridor B (Marsland et al. 2000): like A; two doors on the right, the first (G) "
        "inset 0.35 m; notice boards above the sonars' height.")


def _build_c() -> Environment:
    right = [Door("door-c1", 4.2, width=1.0, depth=0.9, frame="brick",
                  description="deeply inset doorway"),
             Crack("crack-c", 7.0, description="crack at about 7 m"),
             Board("board-1", 8.3, width=0.9, z=(0.45, 1.45), description="low display board"),
             Board("board-2", 9.4, width=0.9, z=(0.45, 1.45), description="low display board"),
             Door("door-r0", -2.5, depth=0.2, frame="brick"),
             Door("door-r3", 13.0, depth=0.2, frame="brick")]
    return corridor_environment(
        "c", 2.1, "brick", "glass", right, [],
        "Corridor C (Marsland et al. 2000): 2.1 m wide, smooth brick (followed, right) and glass "
        "(left), a deeply inset doorway, low laminated display boards near the end, a crack at 7 m.",
        extra=_glazing_bars(2.1))


def _glazing_bars(y: float, spacing: float = 1.2, width: float = 0.05, depth: float = 0.04):
    """Vertical glazing bars on the corridor side of a glass wall (chosen: every 1.2 m).

    A glazed partition is held by bars between its panes; each stands a few
    centimetres proud of the glass, so its two front edges scatter and the
    corners it makes with the glass retro-reflect (Kuc & Siegel, 1987).
    """
    def add(b: MapBuilder) -> None:
        for x in np.arange(-_MARGIN + 0.3, ROUTE_LENGTH + _MARGIN, spacing):
            a, c = x - width / 2, x + width / 2
            b.polyline([(a, y), (a, y - depth), (c, y - depth), (c, y)], "metal")
            b.edge((a, y - depth), FRAME_EDGE_RANGE)
            b.edge((c, y - depth), FRAME_EDGE_RANGE)
    return add


def _build_control() -> Environment:
    b = MapBuilder()
    x0, x1, y1 = -4.0, 12.0, 10.0
    b.polyline([(x0, 0.0), (x1, 0.0), (x1, y1), (x0, y1)], "breezeblock", closed=True)
    d = WallFollower().distance
    course = ((0.0, d), (1.8, d), (3.4, 3.2), (4.4, 3.2), (6.0, d), (11.5, d))
    return Environment(
        "control", b.build(), WaypointFollower(course), (0.0, d, 0.0), np.array(course),
        ROUTE_LENGTH,
        "Control area (Marsland et al. 2000): a large open hall; the route follows a wall, turns "
        "into the middle and returns to the wall.")


_BUILDERS = {
    "a": functools.partial(corridor_a, False),
    "a-star": functools.partial(corridor_a, True),
    "b": _build_b,
    "c": _build_c,
    "control": _build_control,
}


def environment_names() -> list[str]:
    """Names of the paper's environments."""
    return list(_BUILDERS)


def _canonical(name: str) -> str:
    key = name.strip().lower()
    if key.startswith("paper-"):
        key = key[len("paper-"):]
    key = key.replace("*", "-star").replace("_", "-")
    if key == "astar":
        key = "a-star"
    return key


@functools.lru_cache(maxsize=None)
def _cached(key: str) -> Environment:
    return _BUILDERS[key]()


def get_environment(name) -> Environment:
    """The paper environment called ``name`` (``"a"``, ``"A*"``, ``"paper-b"``...), or ``name`` itself if it is one."""
    if isinstance(name, Environment):
        return name
    key = _canonical(str(name))
    if key not in _BUILDERS:
        raise ValueError(f"Unknown environment {name!r}; known: {', '.join(_BUILDERS)}.")
    return _cached(key)


