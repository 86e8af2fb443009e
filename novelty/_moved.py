"""Module paths that moved: importing one still works, with a ``FutureWarning`` that says where its names went.

When the readers were put in folders by layer, and the task builders into
one package, some module paths disappeared: ``novelty.io.sweeps`` is now
:mod:`novelty.io.scans.sweeps`, :mod:`novelty.io.scans.sweep_rings` and
:mod:`novelty.io.recording`, for one. :data:`MOVED` lists each old path and
the modules its names went to, in the order they are looked for. Importing
an old path gives a module whose names are those modules' (read and set
through to them), after a ``FutureWarning`` that names the new homes; the
old paths will be removed in a future release. Names that users import from
a package (``from novelty.io import read_rings``) never moved and never warn.

:func:`install` puts the finder in :data:`sys.meta_path` (``import
novelty`` does it); it answers for the paths of :data:`MOVED` only, after
every file of the package has been looked for, so a module that exists is
never shadowed.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import types
import warnings

__all__ = ["MOVED", "install"]

#: old module path -> the modules its names went to, looked in in this order
MOVED: dict[str, tuple[str, ...]] = {
    # the ROS message layer
    "novelty.io.caps": ("novelty.io.ros.caps",),
    "novelty.io.messages": ("novelty.io.ros.messages",),
    "novelty.io.wire": ("novelty.io.ros.wire",),
    "novelty.io.quaternions": ("novelty.io.ros.quaternions",),
    "novelty.io.clouds": ("novelty.io.ros.clouds",),
    "novelty.io.decoders": ("novelty.io.ros.decoders",),
    # the formats and the bag of either kind
    "novelty.io.bag1": ("novelty.io.ros1.bag1",),
    "novelty.io.chunks": ("novelty.io.ros1.chunks",),
    "novelty.io.ros2_inflation": ("novelty.io.ros2.inflation",),
    "novelty.io.rosbag": ("novelty.io.bags.rosbag",),
    "novelty.io.report": ("novelty.io.bags.report",),
    # frames
    "novelty.io.tf": ("novelty.io.frames.tf",),
    "novelty.io.mounts": ("novelty.io.frames.mounts",),
    "novelty.io.posing": ("novelty.io.frames.posing",),
    # scans
    "novelty.io.sectors": ("novelty.io.scans.laser_sectors",),
    "novelty.io._sweep_kernels": ("novelty.io.scans._sweep_kernels",),
    "novelty.io.assembly": ("novelty.io.scans.assembly",),
    "novelty.io.merge": ("novelty.io.scans.merge",),
    "novelty.io.sonar_rings": ("novelty.io.scans.sonar_rings",),
    "novelty.io.sweep_rings": ("novelty.io.scans.sweep_rings",),
    "novelty.io.objects.points": ("novelty.io.scans.points",),
    "novelty.maps.points": ("novelty.io.scans.points",),
    # a whole recording
    "novelty.io.sweeps": ("novelty.io.scans.sweeps", "novelty.io.scans.sweep_rings", "novelty.io.recording.readers",
                          "novelty.io.recording.reading", "novelty.io.recording.carmen_sweeps",
                          "novelty.io.recording.bag_sweeps"),
    "novelty.io.bag_sweeps": ("novelty.io.recording.bag_sweeps",),
    "novelty.io.plotting": ("novelty.io.recording.plotting",),
    # the task builders that were in novelty.io
    "novelty.io.tasks": ("novelty.tasks.recordings",),
    "novelty.io.places": ("novelty.tasks.places",),
    "novelty.io.radish": ("novelty.tasks.radish",),
    "novelty.io.objects": ("novelty.tasks.objects",),
    "novelty.io.objects.labels": ("novelty.tasks.objects.casting",),
    "novelty.io.objects.tasks": ("novelty.tasks.objects.object_tasks",),
    "novelty.io.objects.radish": ("novelty.tasks.radish",),
    "novelty.io.objects.shapes": ("novelty.tasks.objects.shapes",),
    "novelty.io.objects.raycast": ("novelty.tasks.objects.raycast",),
    "novelty.io.objects.placement": ("novelty.tasks.objects.placement",),
    # tables of scans
    "novelty.datasets.tables": ("novelty.io.tables.table",),
    "novelty.datasets.columns": ("novelty.io.tables.columns",),
    "novelty.datasets._files": ("novelty.io.tables.data_files",),
    "novelty.datasets.labels": ("novelty.io.tables.labels",),
    "novelty.datasets.smoothing": ("novelty.io.tables.smoothing",),
}


class MovedModule(types.ModuleType):
    """An old module path: its names read (and set) in the modules they moved to."""

    def _targets(self):
        return [importlib.import_module(target) for target in MOVED[self.__name__]]

    def __getattr__(self, name: str):
        if not name.startswith("__"):
            for target in self._targets():
                if hasattr(target, name):
                    return getattr(target, name)
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r} (its names moved to "
                             f"{', '.join(MOVED[self.__name__])})")

    def __setattr__(self, name: str, value) -> None:
        if not name.startswith("__") and not isinstance(value, types.ModuleType):   # not a submodule, set on import
            for target in self._targets():
                if hasattr(target, name):
                    setattr(target, name, value)
                    return
        super().__setattr__(name, value)

    def __dir__(self):
        return sorted({name for target in self._targets() for name in dir(target) if not name.startswith("__")})


class _Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds the old paths of :data:`MOVED`, nothing else."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname not in MOVED:
            return None
        # an old package whose modules moved too: a package still, so that they are found under it
        package = any(old.startswith(fullname + ".") for old in MOVED)
        return importlib.util.spec_from_loader(fullname, self, is_package=package)

    def create_module(self, spec):
        return MovedModule(spec.name)

    def exec_module(self, module) -> None:
        targets = MOVED[module.__name__]
        names = [name for target in module._targets() for name in getattr(target, "__all__", ())]
        module.__all__ = list(dict.fromkeys(names))
        warnings.warn(f"{module.__name__} is deprecated and will be removed in a future release: import its names "
                      f"from {' or '.join(targets)}.", FutureWarning, stacklevel=_importer_level())


def _importer_level() -> int:
    """The stack level of the code that imports the old path, past this module (``warnings.warn`` itself
    passes over the import machinery's frames when it counts)."""
    level, frame = 1, sys._getframe(1)
    while frame is not None and (frame.f_code.co_filename == __file__
                                 or frame.f_code.co_filename.startswith("<frozen importlib")):
        if frame.f_code.co_filename == __file__:
            level += 1
        frame = frame.f_back
    return level


_FINDER = _Finder()


def install() -> None:
    """Put the finder of the old paths last in :data:`sys.meta_path` (once)."""
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_FINDER)
