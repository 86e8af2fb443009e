"""A simulated sonar world: a Nomad 200-like robot in the paper's corridors.

Marsland, Nehmzow & Shapiro (2000) trained their novelty filter on the 16
sonars of a Nomad 200 following corridor walls. Their logs were never
published; this subpackage rebuilds the setting:

- :mod:`~novelty.sonar.materials` how surfaces return echoes;
- :mod:`~novelty.sonar.world` and :mod:`~novelty.sonar.layout` maps;
- :mod:`~novelty.sonar.robot` the robot; :mod:`~novelty.sonar.ranger` the sonar;
- :mod:`~novelty.sonar.controller` wall following with run-to-run variation;
- :mod:`~novelty.sonar.preprocessing` the paper's threshold/normalise/invert/average;
  :class:`~novelty.sonar.preprocessor.SonarPreprocessor` the same as a
  scikit-learn transformer (imported on first use: it needs scikit-learn);
- :mod:`~novelty.sonar.environments` the paper's maps A, A*, B, C and control;
- :mod:`~novelty.tasks.inspection` seeded corridors with inserted novelties;
- :mod:`~novelty.sonar.plotting` figures (needs matplotlib).

>>> from novelty import sonar
>>> ds = sonar.simulate("a", runs=1, seed=0)
>>> ds.X.shape, bool(ds.X.min() >= 0 and ds.X.max() <= 1)
((100, 16), True)
"""

from __future__ import annotations

from .controller import RunVariation, WallFollower, WaypointFollower
from .environments import Environment, corridor_a, environment_names, get_environment
from .materials import MATERIALS, Material
from .preprocessing import bin_by_distance, preprocess
from .ranger import PolaroidRanger
from .robot import NOMAD_200, Robot
from .simulate import simulate, simulate_rings, simulate_run, write_dataset
from .world import Feature, MapBuilder, WorldMap

__all__ = [
    "simulate", "simulate_run", "simulate_rings", "write_dataset",
    "Environment", "get_environment", "environment_names", "feature_table",
    "PolaroidRanger", "Robot", "NOMAD_200", "Material", "MATERIALS",
    "RunVariation", "WallFollower", "WaypointFollower",
    "preprocess", "bin_by_distance", "Feature", "MapBuilder", "WorldMap", "corridor_a",
    "plot_map", "plot_scans", "SonarPreprocessor",
]


def __getattr__(name: str):
    if name == "SonarPreprocessor":  # imported on first use: scikit-learn is slow to import
        # deferred: the transformer imports scikit-learn; the simulator does not
        from .preprocessor import SonarPreprocessor

        return SonarPreprocessor
    raise AttributeError(f"module 'novelty.sonar' has no attribute {name!r}")


def feature_table(environment) -> list[dict]:
    """The features of a paper environment (id, kind, position along the route, side, ...)."""
    return get_environment(environment).feature_table()


def plot_map(*args, **kwargs):
    """Draw a map with the route and one scan's sonar returns (see :func:`novelty.sonar.plotting.plot_map`)."""
    # optional dependency (matplotlib), imported only to draw
    from .plotting import plot_map as _plot_map

    return _plot_map(*args, **kwargs)


def plot_scans(*args, **kwargs):
    """Draw a run's scan sequence as an image (see :func:`novelty.sonar.plotting.plot_scans`)."""
    # optional dependency (matplotlib), imported only to draw
    from .plotting import plot_scans as _plot_scans

    return _plot_scans(*args, **kwargs)
