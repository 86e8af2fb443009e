"""A Polaroid-like ultrasonic ranger, simulated for a whole sonar ring at once.

Each transducer sends a pulse into a cone and reports the range of the
*first* echo loud enough to cross its detection threshold, or its maximum
range when none does (Polaroid, 1987; Leonard & Durrant-Whyte, 1992, ch. 2).
The cone is sampled with ``n_rays`` rays spread evenly across it.

Beam
----
The transducer is modelled as a circular piston of radius ``a``; its main
lobe ends at the first null, ``sin(theta_0) = 0.61 * lambda / a``, which for
the Polaroid 600-series transducer (a = 19.2 mm, lambda = 6.9 mm at
49.4 kHz) is about 12.7 degrees: a cone about 25 degrees wide (Kuc & Siegel,
1987, section II). Inside it the one-way amplitude gain is the Gaussian
approximation of the piston pattern, ``D(w) = exp(-(k a sin w)^2 / 8)``,
which has the same curvature on the axis. ``w`` is the angle off the axis,
combining the ray's horizontal offset with the elevation of the surface hit
(see :func:`~novelty.sonar.geometry.elevation_offset`), so low and high
objects are heard only at the beam's edge, weakly, or not at all.

Echoes
------
A ray's first surface, at distance ``t1`` and incidence ``theta``, gives a
direct echo of strength ``reflectivity * exp(-(2 theta)^2 / (2 lobe^2)) *
D(w)^2`` (:mod:`novelty.sonar.materials`, equation (1)); it is heard when the
strength is at least 1 and ``t1`` is beyond the blanking distance
``min_range``. Otherwise the mirrored part of the pulse travels on; if the
second surface sends enough of it back towards the transducer (its lobe
around the mirror direction, times ``D`` of the arrival angle), the ranger
hears a *multipath* echo at half the total path length, longer than the true
range (Kuc & Siegel, 1987; Leonard & Durrant-Whyte, 1992, section 2.3). This
also makes concave corners, which send a pulse straight back after two
bounces, strong targets, as observed with real sonars. The return leg is not
tested for occlusion, and only one bounce is followed.

Edges (door frames, the lips of a crack) scatter weakly in every direction;
an edge heard on the axis up to ``R`` metres has strength ``(R / r)^2 D(w)^2``
at range ``r`` (a point scatterer loses more with range than a plane, whose
loss the ranger's time-varying gain makes up for; Polaroid, 1987).

Readings then get Gaussian range noise of standard deviation ``noise_sd +
noise_fraction * range`` (the module's stated accuracy is about 1 % of the
range; Polaroid, 1987), and each reading is lost (maximum range) with
probability ``dropout``. With ``resolution`` set, readings are finally
rounded to its multiples: 0.0254 m gives the whole inches the Nomad 200
reports (Nomadic Technologies, 1997); the default keeps them continuous.

The model is one module although it is long: the beam, the direct, multipath
and edge echoes and the noise act together on every ray of one reading, and
apart each piece would be read without the others that decide what it does.

References
----------
Polaroid Corporation (1987). Ultrasonic Ranging System (handbook and 6500
series ranging module data sheet). Cambridge, MA.

Kuc, R. & Siegel, M. W. (1987). Physically based simulation model for
acoustic sensor robot navigation. IEEE Trans. PAMI, 9(6), 766-778.

Leonard, J. J. & Durrant-Whyte, H. F. (1992). Directed Sonar Sensing for
Mobile Robot Navigation. Kluwer.

Nomadic Technologies (1997). Nomad 200 User's Guide: the Sensus 200 sonar
system ranges from 6 to 255 in (0.15-6.5 m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .geometry import elevation_offset, mirror, ray_segment_distances, segment_normals, wrap_angle
from .robot import NOMAD_200, Robot
from .world import WorldMap

__all__ = ["PolaroidRanger", "RingEchoes", "INCH"]

#: One inch (m): the Nomad 200 reports sonar ranges in whole inches.
INCH = 0.0254

_RAYS_PER_CHUNK = 6000


@dataclass(frozen=True)
class RingEchoes:
    """What one batch of sonar rings heard and saw.

    Attributes
    ----------
    ranges : ndarray of shape (n_rings, n_sonars)
        Noiseless first-echo ranges (m); ``inf`` where nothing was heard.
    perceived : ndarray of shape (n_rings, n_features) of bool
        Whether each map feature shaped some sonar's reading nearer than
        the salient range (see :meth:`PolaroidRanger.cast`): it sent the first echo (directly, as either
        surface of a multipath echo, or from one of its edges), or it is an
        opening that the sonar looked through, nearer than its echo (plus
        ``footprint_margin``), where the missing surface would have echoed.
    source : ndarray of shape (n_rings, n_sonars) of int
        0 no echo, 1 direct, 2 multipath, 3 edge (for tests and figures).
    """

    ranges: np.ndarray
    perceived: np.ndarray
    source: np.ndarray


@dataclass(frozen=True)
class PolaroidRanger:
    """The sonar model (see the module docstring for the physics and sources).

    Parameters
    ----------
    frequency : float, default=49.4e3
        Pulse frequency (Hz) of the Polaroid ranging module (Polaroid, 1987).
    speed_of_sound : float, default=343.0
        m/s in air at 20 C.
    transducer_radius : float, default=0.0192
        Radius ``a`` (m) of the 600-series electrostatic transducer's face,
        approximately (Polaroid, 1987); sets the beam width.
    n_rays : int, default=9
        Rays sampling each cone (about 3 degrees apart).
    min_range : float, default=0.15
        Blanking distance (m): nearer echoes are not heard (6 in; Nomadic
        Technologies, 1997).
    max_range : float, default=6.5
        The reading when no echo is heard (255 in; Nomadic Technologies, 1997).
    noise_sd : float, default=0.01
        Constant part of the range noise's standard deviation (m), approximately.
    noise_fraction : float, default=0.01
        Part of the noise's standard deviation proportional to the range (the
        module's 1 % accuracy; Polaroid, 1987).
    dropout : float, default=0.001
        Probability that a reading is lost (maximum range), approximately: a
        missed echo now and then, about one reading in 1000.
    multipath : bool, default=True
        Whether to follow one specular bounce.
    edges : bool, default=True
        Whether edges (door frames, the lips of a crack) send echoes.
    resolution : float or None, default=None
        Step (m) to which readings are rounded (``INCH`` for the Nomad's
        whole inches); None keeps them continuous.
    footprint_margin : float, default=0.05
        Distance (m) beyond a sonar's echo still counted as inside its
        footprint (about the pulse's spatial length), for ground truth.
    """

    frequency: float = 49.4e3
    speed_of_sound: float = 343.0
    transducer_radius: float = 0.0192
    n_rays: int = 9
    min_range: float = 0.15
    max_range: float = 6.5
    noise_sd: float = 0.01
    noise_fraction: float = 0.01
    dropout: float = 0.001
    multipath: bool = True
    footprint_margin: float = 0.05
    edges: bool = True
    resolution: float | None = None

    def __post_init__(self):
        if self.resolution is not None and not self.resolution > 0:
            raise ValueError(f"resolution must be a positive step in metres or None; got {self.resolution!r}.")

    # ------------------------------------------------------------------ beam
    @property
    def wavelength(self) -> float:
        return self.speed_of_sound / self.frequency

    @property
    def beam_half_angle(self) -> float:
        """Half-width (radians) of the main lobe: the piston's first null."""
        return math.asin(min(1.0, 0.61 * self.wavelength / self.transducer_radius))

    def gain(self, off_axis) -> np.ndarray:
        """One-way amplitude gain ``D(w)`` at ``off_axis`` radians (0 outside the cone)."""
        w = np.asarray(off_axis, dtype=np.float64)
        ka = 2.0 * math.pi * self.transducer_radius / self.wavelength
        g = np.exp(-((ka * np.sin(w)) ** 2) / 8.0)
        return np.where(np.abs(w) <= self.beam_half_angle, g, 0.0)

    def ray_offsets(self) -> np.ndarray:
        """Horizontal offsets (radians) of the rays sampling each cone."""
        h = self.beam_half_angle
        return np.linspace(-h, h, self.n_rays) if self.n_rays > 1 else np.zeros(1)

    # ----------------------------------------------------------------- rings
    def cast(self, world: WorldMap, poses, robot: Robot = NOMAD_200,
             salient_range: float = 2.0) -> RingEchoes:
        """Noiseless first echoes of every sonar for every pose (x, y, heading).

        ``salient_range`` (m) bounds the ground truth: a feature is perceived
        only through readings nearer than this. The default, 2 m, is where the
        paper's encoding (threshold 4 m) gives an input of at least 0.5; a
        faint reading at 3.9 m (input 0.025) hardly changes a perception.
        """
        poses = np.atleast_2d(np.asarray(poses, dtype=np.float64))
        sensor_pos, sensor_axis = robot.sonar_poses(poses)
        n_poses, n_sonars = sensor_axis.shape
        per_chunk = max(1, _RAYS_PER_CHUNK // (n_sonars * self.n_rays))
        ranges = np.empty((n_poses, n_sonars))
        source = np.empty((n_poses, n_sonars), dtype=np.int8)
        perceived = np.zeros((n_poses, len(world.features)), dtype=bool)
        scene = _Scene(world, self, robot.sonar_height)
        for start in range(0, n_poses, per_chunk):
            sl = slice(start, start + per_chunk)
            r, src, seen = scene.rings(sensor_pos[sl], sensor_axis[sl], salient_range)
            ranges[sl], source[sl], perceived[sl] = r, src, seen
        return RingEchoes(ranges, perceived, source)

    def read(self, ranges: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Readings as the module reports them: noise, dropouts, limits.

        Unheard echoes (``inf``) and dropouts read ``max_range``.
        """
        ranges = np.asarray(ranges, dtype=np.float64)
        heard = np.isfinite(ranges)
        clean = np.where(heard, ranges, self.max_range)
        sd = self.noise_sd + self.noise_fraction * clean
        noisy = clean + sd * rng.standard_normal(ranges.shape)
        lost = rng.random(ranges.shape) < self.dropout
        out = np.clip(noisy, self.min_range, self.max_range)
        out = np.where(heard & ~lost, out, self.max_range)
        if self.resolution is not None:
            out = np.round(out / self.resolution) * self.resolution
        return out


class _Scene:
    """Per-map arrays prepared once for many rings."""

    def __init__(self, world: WorldMap, ranger: PolaroidRanger, height: float):
        self.world = world
        self.ranger = ranger
        self.height = height
        props = world.material_table()
        self.refl = props["reflectivity"]
        self.lobe = props["lobe"]
        self.specular = props["specular"]
        self.transparent = props["transparent"]
        self.normals = segment_normals(world.p0, world.p1) if world.n_segments else np.zeros((0, 2))
        self.half = ranger.beam_half_angle
        self.spans = (world.z[:, 0] <= height) & (world.z[:, 1] >= height)
        self.offsets = ranger.ray_offsets()

    def _near(self, points: np.ndarray) -> np.ndarray:
        """Segments any part of which lies within max_range of the points' bounding box."""
        w = self.world
        lo = points.min(axis=0) - self.ranger.max_range
        hi = points.max(axis=0) + self.ranger.max_range
        seg_lo = np.minimum(w.p0, w.p1)
        seg_hi = np.maximum(w.p0, w.p1)
        return np.flatnonzero(np.all((seg_hi >= lo) & (seg_lo <= hi), axis=1))

    def _visible_distances(self, origins, dirs, cols, path_before, offsets):
        """Distances to the segments ``cols`` that the beam can hear at their height."""
        w = self.world
        t = ray_segment_distances(origins, dirs, w.p0[cols], w.p1[cols])
        off = np.broadcast_to(np.abs(offsets)[:, None], t.shape)
        # only surfaces that do not span the sonar's height need the vertical test
        partial = np.flatnonzero(~self.spans[cols])
        if partial.size:
            off = off.copy()
            c = cols[partial]
            elev = elevation_offset(t[:, partial] + path_before[:, None], w.z[c, 0], w.z[c, 1],
                                    self.height)
            off[:, partial] = np.hypot(off[:, partial], elev)
            t[:, partial] = np.where(off[:, partial] <= self.half, t[:, partial], np.inf)
        return t, off

    def rings(self, sensor_pos, sensor_axis, salient_range):
        ranger = self.ranger
        n_poses, n_sonars = sensor_axis.shape
        k = self.offsets.size
        origins = np.repeat(sensor_pos.reshape(-1, 2), k, axis=0)                  # (n, 2)
        phi = np.tile(self.offsets, n_poses * n_sonars)                            # (n,)
        angle = np.repeat(sensor_axis.reshape(-1), k) + phi
        dirs = np.stack([np.cos(angle), np.sin(angle)], axis=1)
        n = origins.shape[0]
        cols = self._near(sensor_pos.reshape(-1, 2))
        best = np.full(n, np.inf)
        src = np.zeros(n, dtype=np.int8)
        seg = np.full(n, -1, dtype=np.intp)
        seg2 = np.full(n, -1, dtype=np.intp)
        t_first = np.full(n, np.inf)
        t_vis = np.full((n, cols.size), np.inf)
        if cols.size:
            t_vis, off = self._visible_distances(origins, dirs, cols, np.zeros(n), phi)
            t_opaque = np.where(self.transparent[cols][None, :], np.inf, t_vis)
            j = np.argmin(t_opaque, axis=1)
            rows = np.arange(n)
            t_first = t_opaque[rows, j]
            hit = np.isfinite(t_first)
            seg = np.where(hit, cols[j], -1)
            normal = self.normals[seg]
            cos_inc = np.clip(np.abs(np.sum(dirs * normal, axis=1)), 0.0, 1.0)
            psi = 2.0 * np.arccos(cos_inc)
            g1 = ranger.gain(off[rows, j])
            strength = self.refl[seg] * np.exp(-0.5 * (psi / self.lobe[seg]) ** 2) * g1 ** 2
            direct = hit & (strength >= 1.0) & (t_first >= ranger.min_range)
            best = np.where(direct, t_first, np.inf)
            src[direct] = 1
            if ranger.multipath:
                todo = np.flatnonzero(hit & ~direct & (self.specular[seg] > 0))
                if todo.size:
                    r_mp, second = self._multipath(todo, origins, dirs, t_first, seg, normal, g1,
                                                   phi, sensor_axis, k, cols)
                    better = r_mp < best[todo]
                    best[todo[better]] = r_mp[better]
                    src[todo[better]] = 2
                    seg2[todo[better]] = second[better]
        # per sonar: the first echo over its rays
        best = best.reshape(n_poses * n_sonars, k)
        ray_src = src.reshape(n_poses * n_sonars, k)
        arg = np.argmin(best, axis=1)
        m = np.arange(best.shape[0])
        sonar_range = best[m, arg]
        sonar_src = np.where(np.isfinite(sonar_range), ray_src[m, arg], 0)
        first_seg = seg.reshape(-1, k)[m, arg]
        second_seg = seg2.reshape(-1, k)[m, arg]
        edge_range, edge_which = self._edges(sensor_pos, sensor_axis)
        use_edge = edge_range < sonar_range
        sonar_range = np.where(use_edge, edge_range, sonar_range)
        sonar_src = np.where(use_edge, 3, sonar_src)
        ranges = sonar_range.reshape(n_poses, n_sonars)
        source = sonar_src.reshape(n_poses, n_sonars).astype(np.int8)
        echo_feature = self._echo_features(sonar_src, sonar_range, first_seg, second_seg,
                                           edge_which, salient_range)
        perceived = self._openings(ranges, t_vis, t_first, cols, dirs, phi, salient_range,
                                   n_poses, n_sonars, k)
        for column in echo_feature:
            rows = np.flatnonzero(column >= 0)
            perceived[rows // n_sonars, column[rows]] = True
        return ranges, source, perceived

    def _echo_features(self, src, rng, first_seg, second_seg, edge_which, salient_range):
        """Feature index (or -1) of each surface that made each sonar's echo: two columns and the edge."""
        w = self.world
        near = rng <= salient_range
        seg_feature = np.append(w.feature, -1)  # index -1 (no segment) maps to -1
        edge_feature = np.append(w.edge_feature, -1)
        first = np.where(near & ((src == 1) | (src == 2)), seg_feature[first_seg], -1)
        second = np.where(near & (src == 2), seg_feature[second_seg], -1)
        edge = np.where(near & (src == 3), edge_feature[edge_which], -1)
        return first, second, edge

    def _multipath(self, todo, origins, dirs, t_first, seg, normal, g1, phi, sensor_axis, k, cols):
        """Range (inf when unheard) and second surface of the mirrored part of each ray in ``todo``."""
        ranger = self.ranger
        d1 = t_first[todo]
        hit1 = origins[todo] + d1[:, None] * dirs[todo]
        d2dir = mirror(dirs[todo], normal[todo])
        t2, _ = self._visible_distances(hit1, d2dir, cols, d1, phi[todo])
        # the pulse leaves the first surface: it cannot meet it again on a plane
        same = cols[None, :] == seg[todo][:, None]
        t2 = np.where(same | self.transparent[cols][None, :], np.inf, t2)
        j2 = np.argmin(t2, axis=1)
        rows = np.arange(todo.size)
        d2 = t2[rows, j2]
        ok = np.isfinite(d2)
        seg2 = cols[j2]
        hit2 = hit1 + np.where(ok, d2, 0.0)[:, None] * d2dir
        sensor = origins[todo]
        back = sensor - hit2
        d3 = np.linalg.norm(back, axis=1)
        back_dir = back / np.maximum(d3, 1e-12)[:, None]
        out_dir = mirror(d2dir, self.normals[seg2])
        psi2 = np.arccos(np.clip(np.sum(back_dir * out_dir, axis=1), -1.0, 1.0))
        axis = np.repeat(sensor_axis.reshape(-1), k)[todo]
        arrival = wrap_angle(np.arctan2(-back_dir[:, 1], -back_dir[:, 0]) - axis)
        z2 = self.world.z[seg2]
        arrival = np.hypot(arrival, elevation_offset(d3, z2[:, 0], z2[:, 1], self.height))
        strength = (self.specular[seg[todo]] * self.refl[seg2]
                    * np.exp(-0.5 * (psi2 / self.lobe[seg2]) ** 2) * g1[todo] * ranger.gain(arrival))
        total = 0.5 * (d1 + d2 + d3)
        heard = ok & (strength >= 1.0) & (total <= ranger.max_range) & (total >= ranger.min_range)
        return np.where(heard, total, np.inf), np.where(heard, seg2, -1)

    def _edges(self, sensor_pos, sensor_axis):
        """Range and index of the first edge echo per sonar (inf and -1 when none)."""
        w = self.world
        flat_pos = sensor_pos.reshape(-1, 2)
        flat_axis = sensor_axis.reshape(-1)
        m = flat_pos.shape[0]
        if w.edges.shape[0] == 0 or not self.ranger.edges:
            return np.full(m, np.inf), np.full(m, -1, dtype=np.intp)
        vec = w.edges[None, :, :] - flat_pos[:, None, :]                      # (m, e, 2)
        r = np.linalg.norm(vec, axis=2)
        bearing = wrap_angle(np.arctan2(vec[..., 1], vec[..., 0]) - flat_axis[:, None])
        elev = elevation_offset(r, w.edge_z[:, 0], w.edge_z[:, 1], self.height)
        off = np.hypot(bearing, elev)
        strength = (w.edge_range[None, :] / np.maximum(r, 1e-9)) ** 2 * self.ranger.gain(off) ** 2
        cand = np.argwhere((strength >= 1.0) & (r >= self.ranger.min_range)
                           & (r <= self.ranger.max_range))
        heard = np.zeros(r.shape, dtype=bool)
        if cand.size:
            # an edge is heard only if no surface stands between it and the sonar
            dist = r[cand[:, 0], cand[:, 1]]
            dirs = vec[cand[:, 0], cand[:, 1]] / dist[:, None]
            cols = self._near(flat_pos)
            t, _ = self._visible_distances(flat_pos[cand[:, 0]], dirs, cols, np.zeros(len(dist)),
                                           np.zeros(len(dist)))
            t = np.where(self.transparent[cols][None, :], np.inf, t)
            heard[cand[:, 0], cand[:, 1]] = t.min(axis=1, initial=np.inf) >= dist - 0.02
        r_heard = np.where(heard, r, np.inf)
        which = np.argmin(r_heard, axis=1)
        first = r_heard[np.arange(m), which]
        return first, np.where(np.isfinite(first), which, -1)

    def _openings(self, ranges, t_vis, t_first, cols, dirs, phi, salient_range,
                  n_poses, n_sonars, k):
        """Per ring, the openings some sonar looked through where a surface would have echoed."""
        w = self.world
        perceived = np.zeros((n_poses, len(w.features)), dtype=bool)
        if not cols.size:
            return perceived
        ap = np.flatnonzero((w.stands_for[cols] >= 0) & (w.feature[cols] >= 0))
        if not ap.size:
            return perceived
        limit = np.minimum(np.where(np.isfinite(ranges), ranges + self.ranger.footprint_margin,
                                    salient_range), salient_range)
        ray_limit = np.minimum(np.repeat(limit.reshape(-1), k), t_first)
        segs = cols[ap]
        crossed = t_vis[:, ap] <= ray_limit[:, None]                            # (n, a)
        # would the surface the opening replaces have sent a direct echo?
        mats = w.stands_for[segs]
        refl = np.array([m.reflectivity for m in w.materials])[mats]
        lobe = np.radians(np.array([m.lobe for m in w.materials]))[mats]
        cos_inc = np.abs(dirs @ self.normals[segs].T)                          # (n, a)
        psi = 2.0 * np.arccos(np.clip(cos_inc, 0.0, 1.0))
        strength = refl * np.exp(-0.5 * (psi / lobe) ** 2) * self.ranger.gain(phi)[:, None] ** 2
        noticed = crossed & (strength >= 1.0)
        per_ring = noticed.reshape(n_poses, n_sonars * k, ap.size).any(axis=1)   # (p, a)
        for j, seg in enumerate(segs):
            perceived[:, w.feature[seg]] |= per_ring[:, j]
        return perceived
