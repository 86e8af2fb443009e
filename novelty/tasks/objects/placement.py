"""Where objects go: read from the user's file, checked against what the robot saw, or drawn by a seed.

- :func:`read_objects`: a CSV (one object a row) or TOML (``[[objects]]``
  tables) file; every field named, every error with its file and line.
- :func:`refusals` / :func:`check_objects`: an object is refused where it
  would stand inside something the robot saw as solid (recorded beams end
  inside it, more than ``deep`` in, in more than ``solid`` of the scans
  that looked at it: a wall, not a person walking by) or on the robot's
  path (the drive between two scans passes within ``clearance`` of it
  while it stands there).
- :func:`draw_objects`: objects drawn by a seed beside the robot's path,
  at places the robot looks at before they appear (so that the place is
  familiar) and passes at least ``min_passes`` times after, sized and
  turned at random, each checked as above.
"""

from __future__ import annotations

import csv
import math
import sys
from dataclasses import replace
from pathlib import Path
from typing import Sequence

import numpy as np

from .casting import cast_all, passes, sightings
from .places import PLACE_TOLERANCE, looks
from .raycast import world_beams
from .shapes import SHAPES, Box, Cylinder

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10: tomli, a dependency there (pyproject.toml)
    import tomli as tomllib

__all__ = ["read_objects", "object_from_fields", "refusals", "check_objects", "draw_objects", "FIELDS"]

#: The fields of each kind of object (besides ``kind``, ``name``, ``start`` and ``end``).
FIELDS = {"box": ("x", "y", "length", "width", "yaw"), "cylinder": ("x", "y", "radius"),
          "wall": ("x1", "y1", "x2", "y2", "thickness")}
_OPTIONAL = {"yaw", "thickness", "start", "end"}


def object_from_fields(fields: dict, where: str = "an object"):
    """A :class:`Box`, :class:`Cylinder` or :class:`Wall` from named fields (``kind`` says which)."""
    kind = str(fields.get("kind", "")).strip().lower()
    if kind not in SHAPES:
        raise ValueError(f"{where}: kind must be one of {', '.join(SHAPES)}; got {fields.get('kind')!r}.")
    allowed = {"kind", "name", "start", "end", *FIELDS[kind]}
    given = {k: v for k, v in fields.items() if v not in (None, "")}
    unknown = sorted(set(given) - allowed)
    if unknown:
        raise ValueError(f"{where}: a {kind} has no field {', '.join(unknown)}; its fields: "
                         f"name, {', '.join(FIELDS[kind])}, start, end.")
    missing = [k for k in ("name", *FIELDS[kind]) if k not in given and k not in _OPTIONAL]
    if missing:
        raise ValueError(f"{where}: a {kind} needs {', '.join(missing)}.")
    values = {}
    for key, value in given.items():
        if key in ("kind", "name"):
            continue
        try:
            values[key] = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{where}: {key} is {value!r}, not a number.") from None
    try:
        return SHAPES[kind](name=str(given["name"]), **values)
    except ValueError as err:
        raise ValueError(f"{where}: {err}") from None


def read_objects(path) -> list:
    """The objects of a CSV or TOML file (by its suffix).

    CSV: a header naming ``kind``, ``name`` and the fields the kinds need
    (:data:`FIELDS`; ``start``, ``end``, ``yaw`` and ``thickness``
    optional), one object a row, empty cells for fields a kind has not.
    TOML: one ``[[objects]]`` table an object, with the same keys.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "objects.csv")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("kind,name,x,y,length,width,radius,start\\nbox,crate,2,1,0.6,0.4,,100\\ncylinder,bin,5,0,,,0.2,\\n")
    >>> [(type(o).__name__, o.name, o.start) for o in read_objects(path)]
    [('Box', 'crate', 100.0), ('Cylinder', 'bin', -inf)]
    """
    path = Path(path)
    if path.suffix.lower() == ".toml":
        with open(path, "rb") as fh:
            try:
                tables = tomllib.load(fh).get("objects")
            except tomllib.TOMLDecodeError as err:
                raise ValueError(f"{path}: not TOML: {err}.") from None
        if not isinstance(tables, list) or not tables:
            raise ValueError(f"{path}: no objects; give one [[objects]] table an object.")
        objects = [object_from_fields(t, f"{path}, object {i + 1}") for i, t in enumerate(tables)]
    elif path.suffix.lower() == ".csv":
        with open(path, newline="", encoding="utf-8") as fh:
            rows = csv.reader(fh)
            header = [h.strip() for h in next(rows, [])]
            if "kind" not in header or "name" not in header:
                raise ValueError(f"{path}: the header must name kind, name and the objects' fields; got {header}.")
            objects = [object_from_fields(dict(zip(header, (c.strip() for c in row))), f"{path}, line {line}")
                       for line, row in enumerate(rows, start=2) if any(c.strip() for c in row)]
        if not objects:
            raise ValueError(f"{path}: no objects (one row an object after the header).")
    else:
        raise ValueError(f"{path}: objects are read from a .csv or .toml file.")
    names = [o.name for o in objects]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"{path}: each object needs its own name; {', '.join(twice)} named twice.")
    return objects


# ------------------------------------------------------------------ refusals
def _solid(obj, sweeps, deep: float) -> tuple[int, int]:
    """Scans that ended a recorded beam more than ``deep`` inside ``obj``, and scans whose beams reached it."""
    ended = looked = 0
    for sweep in sweeps:
        origins, angles = world_beams(sweep)
        r = np.asarray(sweep.ranges, dtype=np.float64)
        reach = obj.entry(origins, np.c_[np.cos(angles), np.sin(angles)])
        long = np.where(np.isnan(r), -np.inf, r)   # a beam of no information reached nothing
        finite = np.isfinite(r)
        ends = origins[finite] + r[finite, None] * np.c_[np.cos(angles[finite]), np.sin(angles[finite])]
        inside = bool(np.any(obj.depth(ends) > deep)) if len(ends) else False
        ended += inside
        looked += bool(np.any(reach < long)) or inside
    return ended, looked


def _on_path(obj, times, poses, clearance: float) -> float | None:
    """The first time the drive between two scans passes within ``clearance`` of ``obj`` while it stands."""
    steps = np.linspace(0.0, 1.0, 21)
    for i in range(len(poses)):
        j = min(i + 1, len(poses) - 1)
        if not (obj.present(times[i]) or obj.present(times[j])):
            continue
        p = poses[i, :2] + steps[:, None] * (poses[j, :2] - poses[i, :2])
        if np.any(obj.depth(p) > -clearance):
            return float(times[i])
    return None


def refusals(objects: Sequence, sweeps: Sequence, *, clearance: float = 0.3, solid: float = 0.5,
             deep: float = 0.05) -> list[str]:
    """Why each refused object is refused (an empty list: all may stand); see the module docstring.

    Parameters
    ----------
    objects : sequence of Box, Cylinder or Wall
    sweeps : sequence of Sweep
        The recording as recorded, with poses.
    clearance : float, default=0.3
        The robot's radius (m): the drive may not pass closer to an object standing there.
    solid : float, default=0.5
        The share of the scans whose beams reached the object that may end a beam inside it.
    deep : float, default=0.05
        How far inside (m) a beam's end must lie to count (the laser's noise on a surface the object touches).
    """
    if not sweeps:
        raise ValueError("No sweeps to check the objects against.")
    times = np.array([s.time for s in sweeps], dtype=np.float64)
    poses = np.array([s.pose for s in sweeps], dtype=np.float64)
    found = []
    for obj in objects:
        ended, looked = _solid(obj, sweeps, deep)
        if ended and ended > solid * looked:
            found.append(f"{type(obj).__name__} {obj.name!r} stands inside something the robot saw as solid: "
                         f"{ended} of the {looked} scans that looked at it ended beams more than {deep} m inside it.")
        when = _on_path(obj, times, poses, clearance)
        if when is not None:
            found.append(f"{type(obj).__name__} {obj.name!r} stands on the robot's path: the robot passed within "
                         f"{clearance} m of it at t={when:.2f} s, while it stood there.")
    return found


def check_objects(objects: Sequence, sweeps: Sequence, **options) -> None:
    """Raise ValueError with every reason if any object is refused (:func:`refusals`, same options)."""
    found = refusals(objects, sweeps, **options)
    if found:
        raise ValueError("Objects refused:\n- " + "\n- ".join(found))


# ------------------------------------------------------------------ drawn by a seed
def _candidate(rng, sweep, sizes, kinds, clearance: float, name: str, start: float):
    """An object beside the robot at ``sweep``, in the free space the sweep saw to one side; or None."""
    x, y, yaw = (float(v) for v in sweep.pose)
    side = rng.choice([-1.0, 1.0])
    origins, angles = world_beams(sweep)
    bearing = yaw + side * math.pi / 2
    beam = int(np.argmin(np.abs((angles - bearing + math.pi) % (2 * math.pi) - math.pi)))
    free = float(sweep.ranges[beam]) if np.isfinite(sweep.ranges[beam]) else 4.0
    size = float(rng.uniform(*sizes))
    low, high = clearance + size / 2 + 0.1, min(free, 4.0) - size / 2 - 0.1
    if high <= low:
        return None
    ahead = float(rng.uniform(-1.0, 1.0))
    lateral = float(rng.uniform(low, high))
    cx = x + ahead * math.cos(yaw) + lateral * math.cos(bearing)
    cy = y + ahead * math.sin(yaw) + lateral * math.sin(bearing)
    kind = kinds[int(rng.integers(len(kinds)))]
    if kind == "cylinder":
        return Cylinder(name, cx, cy, size / 2, start=start)
    if kind == "box":
        return Box(name, cx, cy, size, float(rng.uniform(sizes[0], size)), float(rng.uniform(0, math.pi)),
                   start=start)
    raise ValueError(f"kinds drawn are 'box' and 'cylinder'; got {kind!r}.")


def draw_objects(sweeps: Sequence, n: int, seed: int, *, start: float, sizes=(0.3, 1.0),
                 kinds=("box", "cylinder"), min_passes: int = 3, before: int = 1, leave: float = 4.0,
                 clearance: float = 0.3, margin: float = 0.1, min_beams: int = 3, within: float = 4.0,
                 unseen: bool = False, tolerance: float = PLACE_TOLERANCE, max_tries: int = 2000) -> list:
    """``n`` objects drawn by ``seed`` beside the robot's path, appearing at ``start`` (s) and staying.

    An anchor scan after ``start`` is drawn, and an object of a size drawn
    in ``sizes`` (m, its largest extent) placed beside the robot there, in
    the free space its scan saw to one side, up to 1 m ahead or behind. It
    is kept when it is not refused (:func:`refusals`), keeps ``clearance``
    from the objects kept before, and is seen (:func:`.labels.sightings`)
    in at least ``before`` passes before ``start`` (had it stood there) and
    ``min_passes`` after. With ``unseen``, it is kept only where no beam of
    the scans before ``start`` passed through or ended in its footprint
    grown by ``tolerance`` (:func:`novelty.tasks.objects.places.looks`): a place the robot had
    never seen (``before`` must then be 0).

    Raises
    ------
    ValueError
        When fewer than ``n`` objects are found in ``max_tries`` draws; the
        message says how many passes the best places got.
    """
    if unseen and before > 0:
        raise ValueError(f"An unseen place was looked at 0 times before the objects appear; got before={before}.")
    sweeps = list(sweeps)
    times = np.array([s.time for s in sweeps], dtype=np.float64)
    poses = np.array([s.pose for s in sweeps], dtype=np.float64)
    anchors = np.flatnonzero(times >= start)
    if not anchors.size:
        raise ValueError(f"No scan at or after start={start}: the objects would never be seen.")
    rng = np.random.default_rng(seed)
    kept: list = []
    best = (0, 0)
    for _ in range(max_tries):
        if len(kept) == n:
            break
        name = f"object-{len(kept) + 1}"
        obj = _candidate(rng, sweeps[int(rng.choice(anchors))], sizes, kinds, clearance, name, -math.inf)
        if obj is None or any(math.hypot(obj.x - o.x, obj.y - o.y) < (obj.size + o.size) / 2 + 2 * clearance
                              for o in kept):
            continue
        # the cheaper test first: the scans before start against the object's place (no draw depends on it)
        if unseen and looks(sweeps[:anchors[0]], [replace(obj, start=start)], tolerance=tolerance, within=within)[0]:
            continue
        seen = sightings(cast_all(sweeps, [obj], margin=margin, within=within).shortened[:, 0], min_beams)
        k = passes(seen, poses, obj, leave)
        early = len(set(k[(times < start) & (k >= 0)].tolist()))
        late = len(set(passes(seen & (times >= start), poses, obj, leave)[times >= start].tolist()) - {-1})
        best = max(best, (min(early, before), late))
        if early < before or late < min_passes:
            continue
        placed = replace(obj, start=start)
        if refusals([placed], sweeps, clearance=clearance):
            continue
        kept.append(placed)
    if len(kept) < n:
        where = "never saw" if unseen else f"looks at {before} time(s)"
        raise ValueError(f"Found {len(kept)} of {n} places in {max_tries} draws (seed {seed}) that the robot "
                         f"{where} before t={start} and passes {min_passes} times after; the "
                         f"best had {best[0]} and {best[1]}. Ask for fewer objects or passes, or an earlier start.")
    return kept

