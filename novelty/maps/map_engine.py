"""The arithmetic of a habituating map: world cells and a synapse bank, in numpy (the specification) or compiled.

A :class:`~novelty.maps.habituating_map.HabituatingMap` holds one engine for its
fitted parts, as the habituating filter does (:mod:`novelty._kernels`), and
asks it two things:

- ``learn(X, dt, stimulus, costs) -> novelty``: the rows in order, each scored by the
  map as it is (equations (1) and (2) of :mod:`novelty.maps.cells`), then
  learned: its tiles made as its cells meet them, its winners and neighbours
  stimulated by the synapse's own step (``Synapse.step`` with several winners),
  the passes of its rays counted (``evidence_lag`` scans later);
- ``score(X, costs) -> novelty``: the same novelty, nothing learned.

``costs`` are what the rows' check worked out (:func:`novelty.maps.grid_kernels.check_costs`):
at most how many cells each row touches and its cones' widths, which the
compiled loops make room by and read the rows with (None: worked out again);
the reference reads each scan whole.

:class:`MapReference` is the readable loop, scan by scan in numpy: the
specification. :class:`MapCompiled` does the same operations in the same order
in one compiled loop per synapse (:mod:`novelty.maps._map_driver`) and gives
the same numbers bit for bit; it holds the state in arrays with room for more
tiles and shows the parts views of the units in use. Which one, and why, is
:func:`choose`'s: compiled when the synapse declares compiled steps and the
kernels are enabled (``NOVELTY_NO_KERNELS`` unset) and ready; while the loop
compiles in the background the reference learns, with the same results.
Scoring is compiled whenever the kernels are enabled (it reads the synapses'
efficacies only, whatever the synapse).
"""

from __future__ import annotations

import warnings

import numpy as np

from .._kernels.compiling import disabled
from .._kernels.params import pack, spec_of
from .cells import ScanCells, WorldCells
from .tiles import TILE_CELLS, GridFullWarning

__all__ = ["MapReference", "MapCompiled", "choose", "wait"]


class MapReference:
    """The map's loop in numpy, on the parts' own arrays (module docstring)."""

    why = "reference"

    def __init__(self, cells: WorldCells, synapse, why: str = "reference"):
        self.cells, self.synapse, self.why = cells, synapse, why
        self.index = cells.index()
        self.passed_by = 0

    # ------------------------------------------------------------------ learning
    def learn(self, X: np.ndarray, dt: np.ndarray, stimulus: float, costs=None) -> np.ndarray:
        self.flush()
        out = np.empty(X.shape[0])
        lag = int(self.cells.evidence_lag)
        for r in range(X.shape[0]):
            scan = self.cells.scan_cells(X[r])
            self._meet(scan)
            out[r] = self._readout(scan.hits)
            hits = self._units(scan.hits)
            self._learn(hits, self._units(scan.neighbours), stimulus, float(dt[r]))
            if lag == 0:
                self._pass(hits, scan)
            else:
                self.cells.pending_ = np.vstack([self.cells.pending_, X[r:r + 1]])
                self.flush()
        return out

    def flush(self) -> None:
        """Count the passes of the pending scans beyond the last ``evidence_lag``, oldest first."""
        while self.cells.pending_.shape[0] > int(self.cells.evidence_lag):
            scan = self.cells.scan_cells(self.cells.pending_[0])
            self._pass(self._units(scan.hits), scan)
            self.cells.pending_ = self.cells.pending_[1:]

    def _meet(self, scan: ScanCells) -> None:
        """Make the tiles of the scan's cells not held, in the order met, as many as there is room for."""
        new = self.cells.new_tiles(scan.met(), self.index)
        if new.size:
            self.index.add(new)
            units = new.size * TILE_CELLS
            self.cells.tiles_ = self.index.tiles
            self.cells.passes_ = np.concatenate([self.cells.passes_, np.zeros(units)])
            self.cells.last_hit_ = np.concatenate([self.cells.last_hit_, np.zeros(units, dtype=np.int64)])
            self.synapse.grow(units)
        self.passed_by += int(np.count_nonzero(self._units(scan.met()) < 0))

    def _units(self, cells: np.ndarray) -> np.ndarray:
        return self.index.units(cells[:, 0], cells[:, 1])

    def _learn(self, hits: np.ndarray, neighbours: np.ndarray, stimulus: float, dt: float) -> None:
        """The scan counted; its hit cells at the first hit of a visit stimulated as winners, with the
        neighbours, by the synapse's step."""
        cells = self.cells
        cells.scans_ += 1
        hits = hits[hits >= 0]
        last = cells.last_hit_[hits]
        cells.last_hit_[hits] = cells.scans_
        gap = int(cells.visit_gap)
        winners = hits if gap == 0 else hits[(last == 0) | (last < cells.scans_ - gap)]
        self.synapse.step(winners, neighbours[neighbours >= 0], stimulus, dt)

    def _pass(self, hits: np.ndarray, scan: ScanCells) -> None:
        """One pass to each cell the scan's rays passed, once, but to its hit cells."""
        passed = np.unique(self._units(scan.passed))
        passed = np.setdiff1d(passed[passed >= 0], hits, assume_unique=False)
        self.cells.passes_[passed] += 1.0

    # ------------------------------------------------------------------ scoring
    def score(self, X: np.ndarray, costs=None) -> np.ndarray:
        return np.array([self._readout(self.cells.scan_cells(X[r], walk=False).hits) for r in range(X.shape[0])])

    def _readout(self, hits: np.ndarray) -> float:
        return self.cells.readout(hits, self.index.units, self.synapse.efficacy_, self.synapse.fresh_efficacy)[1]


class MapCompiled(MapReference):
    """The same loop compiled (module docstring): learning by the synapse's loop when it is given, scoring
    by the cells' kernels."""

    why = "compiled"

    def __init__(self, cells, synapse, driver=None):
        super().__init__(cells, synapse, "compiled" if driver is not None else "reference (compiling)")
        from . import _cells_kernels  # numba: imported where a compiled engine is made (a second, once)

        self._kernels = _cells_kernels
        self.driver = driver
        if driver is not None:
            self.learn = self._learn_compiled
            self._hold()

    # ------------------------------------------------------------------ the state
    def _hold(self) -> None:
        """The state in arrays of the engine's own with room for more tiles, the parts shown views of them."""
        cells, synapse = self.cells, self.synapse
        self._spec = spec_of(synapse)
        self._c_record, self._s_record = pack(cells), pack(synapse)
        n = cells.tiles_.size
        self._make_room(max(16, n), n, cells.tiles_, cells.passes_, cells.last_hit_,
                        [getattr(synapse, name) for name in self._spec.arrays])
        self._counters = np.zeros(5, dtype=np.int64)
        self._counters[self._kernels.N_TILES] = n
        self._counters[self._kernels.SCANS] = cells.scans_
        self._show(n)

    def _make_room(self, capacity: int, n: int, tiles, passes, last_hit, s_arrays) -> None:
        """Arrays for ``capacity`` tiles holding the first ``n`` of those given, the room fresh."""
        from . import grid_kernels as grid  # numba, as above

        capacity = min(capacity, max(self.cells.max_tiles, n))
        units, used = capacity * TILE_CELLS, n * TILE_CELLS
        self._tiles = np.full(capacity, -1, dtype=np.int64)
        self._tiles[:n] = tiles[:n]
        self._passes = np.zeros(units)
        self._passes[:used] = passes[:used]
        self._last_hit = np.zeros(units, dtype=np.int64)
        self._last_hit[:used] = last_hit[:used]
        self._s_arrays = []
        for own in s_arrays:
            a = np.empty((units,) + own.shape[1:], dtype=own.dtype)
            a[:used] = own[:used]
            self._s_arrays.append(a)
        self.driver.module.fresh(used, units, *self._s_arrays, self._s_record.view(np.uint8))
        self._bits = grid.bits_for(capacity)
        self._table = grid.table_of(self._tiles, n, self._bits)
        self._stamp = np.zeros(units, dtype=np.int64)
        self._mark = np.zeros(units, dtype=np.bool_)
        self._rows = np.empty(units, dtype=np.int64)

    def _show(self, n: int) -> None:
        """The parts' arrays as views of the first ``n`` tiles' units of the engine's."""
        used = n * TILE_CELLS
        self.cells.tiles_ = self._tiles[:n]
        self.cells.passes_ = self._passes[:used]
        self.cells.last_hit_ = self._last_hit[:used]
        for name, a in zip(self._spec.arrays, self._s_arrays):
            setattr(self.synapse, name, a[:used])
        self.index = self.cells.index()

    # ------------------------------------------------------------------ learning
    def _learn_compiled(self, X: np.ndarray, dt: np.ndarray, stimulus: float, costs=None) -> np.ndarray:
        cells, k = self.cells, self._kernels
        self.flush()
        n = (X.shape[1] - 3) // 3
        c = pack(cells)
        if c.dtype != self._c_record.dtype or self._counters[k.N_TILES] != cells.tiles_.size:
            self._hold()   # a parameter's type changed, or the state was replaced: read it again
        self._c_record = c
        self._counters[k.SCANS] = cells.scans_
        most_cells, widths, most_rays = self._costs(X, n, costs)
        most_cells += 8 * most_rays + 1
        out = np.empty(X.shape[0])
        done = 0
        self._counters[k.PASSED] = 0
        while True:
            done = self.driver.module.drive(
                X, widths, done, dt, float(stimulus), n, c.view(np.uint8), self._tiles, self._table, self._bits,
                self._passes, self._last_hit, self._counters, cells.max_tiles, *self._s_arrays,
                self._s_record.view(np.uint8), float(self.synapse.fresh_efficacy), cells.pending_, self._stamp,
                self._mark, self._rows, most_rays, most_cells, out)
            if done == X.shape[0]:
                break
            held = int(self._counters[k.N_TILES])
            self._make_room(max(int(self._counters[k.NEED]), 2 * self._tiles.size), held, self._tiles,
                            self._passes, self._last_hit, self._s_arrays)
        self.passed_by += int(self._counters[k.PASSED])
        self._show(int(self._counters[k.N_TILES]))
        vars(cells)["scans_"] = int(self._counters[k.SCANS])
        lag = int(cells.evidence_lag)
        if lag:
            cells.pending_ = np.vstack([cells.pending_, X])[-lag:]
        return out

    def _costs(self, X: np.ndarray, n: int, costs) -> tuple[int, np.ndarray, int]:
        """At most how many cells a row touches, the rows' cones' widths (``costs``, as the rows' check worked
        them out, else worked out here) and the most rays of a row, the pending scans' included (walked again
        for their passes): what the loops make room for."""
        if costs is None:
            costs = self._bounds(X, n)
        sizes, widths = costs
        most_rays = int(self._kernels.most_rays(X, n, pack(self.cells)[0], widths)) if X.shape[0] else 1
        most_cells = int(sizes.max(initial=0))
        pending = self.cells.pending_
        if pending.shape[0]:
            sizes, held = self._bounds(pending, n)
            most_rays = max(most_rays, int(self._kernels.most_rays(pending, n, pack(self.cells)[0], held)))
            most_cells = max(most_cells, int(sizes.max()))
        return most_cells, widths, most_rays

    def _bounds(self, X: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
        from . import grid_kernels as grid  # numba, as above

        cells = self.cells
        sizes, widths = np.empty(X.shape[0], dtype=np.int64), np.empty(X.shape[0])
        grid.scan_bounds(X, n, float(cells.cell_size), float(cells.max_range),
                         -1.0 if isinstance(cells.arc, str) else float(cells.arc), float(cells.cell_size),
                         int(cells.max_scan_cells), sizes, widths)
        return sizes, widths

    # ------------------------------------------------------------------ scoring
    def score(self, X: np.ndarray, costs=None) -> np.ndarray:
        from . import grid_kernels as grid  # numba, as above

        cells, k = self.cells, self._kernels
        n = (X.shape[1] - 3) // 3
        c = pack(cells)
        tiles = np.ascontiguousarray(cells.tiles_, dtype=np.int64)
        bits = grid.bits_for(max(tiles.size, 1))
        out = np.empty(X.shape[0])
        if X.shape[0]:
            _, widths, most = self._costs(X, n, costs)
            k.score(X, n, c[0], widths, grid.table_of(tiles, tiles.size, bits), bits, tiles,
                    np.ascontiguousarray(cells.passes_), np.ascontiguousarray(self.synapse.efficacy_, dtype=np.float64),
                    float(self.synapse.fresh_efficacy), most, out)
        return out


def choose(cells: WorldCells, synapse):
    """A new engine for the fitted parts (their state checked): compiled where it may be, else the reference,
    with the reason (module docstring)."""
    if disabled():
        return MapReference(cells, synapse, "reference (NOVELTY_NO_KERNELS)")
    if spec_of(synapse) is None:
        return _scoring_only(cells, synapse, f"reference ({type(synapse).__name__} declares no compiled steps)")
    from ._map_driver import driver_of  # the loop's generator (its modules import numba when compiled)

    compiled = driver_of(cells, synapse)
    module = compiled.get()
    if module is None:
        why = "reference (compiling)" if compiled.compiling else f"reference (kernels unavailable: {compiled.error})"
        return _scoring_only(cells, synapse, why, compiled)
    return MapCompiled(cells, synapse, compiled)


def _scoring_only(cells, synapse, why: str, pending=None):
    engine = MapCompiled(cells, synapse, None)
    engine.why, engine.pending = why, pending
    return engine


def wait(cells: WorldCells, synapse, timeout: float | None = None) -> bool:
    """Compile (or load) the loop of these parts now; whether it is ready (benchmarks and tests)."""
    if disabled() or spec_of(synapse) is None:
        return False
    from ._map_driver import driver_of

    return driver_of(cells, synapse).wait(timeout) is not None


def warn_full(cells: WorldCells, passed_by: int, stacklevel: int = 4) -> None:
    """Say that cells beyond ``max_cells`` were read as never met (when any were)."""
    if passed_by:
        warnings.warn(f"{type(cells).__name__} holds max_cells = {cells.max_cells} cells: {passed_by} cells beyond "
                      "them were read as never met and not learned (raise max_cells, or cell_size).",
                      GridFullWarning, stacklevel=stacklevel)
