"""Name registries for detectors, clusterers, synapses and datasets.

One :class:`Registry` per kind of component, all of them here:
:func:`of_kind` finds the one of a kind, :func:`build` makes a component of
a kind from a name or an instance. Each maps a short lower-case name
(``"som"``, ``"stanley"``, ``"hsom"``) to a class or factory. Three sources
feed a registry, in this order of precedence:

1. built-ins, known by dotted path (``"novelty.clusterers.som:SOM"``) and
   imported only when first asked for, so ``import novelty`` stays cheap;
2. objects registered at run time with :meth:`Registry.register` (usable as a
   decorator);
3. third-party plugins advertised through a Python entry-point group
   (``novelty.clusterers``, ``novelty.synapses``, ``novelty.detectors``,
   ``novelty.datasets``), read on the first look-up, never at import time.

Duplicate names are refused unless ``replace=True``; an unknown name is
answered with the close matches and the list of known names; an unknown
parameter with the valid ones.

The registries are one module although it is long: the :class:`Registry`
class, the four registries made from it and the two helpers over them are
the one place a name becomes a component, and the built-in names read best
beside the rules that look them up; the datasets' and tasks' names are
their builders' table (:data:`novelty.tasks.registered.TASKS`), beside them.
"""

from __future__ import annotations

import difflib
import importlib
import inspect
from importlib.metadata import entry_points
from types import MappingProxyType
from typing import Any, Callable, Mapping

from ._messages import unknown_parameters
from .tasks.registered import TASKS

__all__ = [
    "Registry",
    "RegistryError",
    "UnknownNameError",
    "InvalidParameterError",
    "valid_parameters",
    "check_parameters",
    "clusterers",
    "synapses",
    "detectors",
    "datasets",
    "KINDS",
    "of_kind",
    "build",
]


class RegistryError(ValueError):
    """A registry look-up or registration that cannot be done."""


class UnknownNameError(RegistryError, KeyError):
    """A name that no registry entry carries."""

    def __str__(self) -> str:  # KeyError would quote the whole message
        return str(self.args[0])


class InvalidParameterError(RegistryError, TypeError):
    """A parameter that the named component does not take."""


def _first_line(obj: Any) -> str:
    doc = inspect.getdoc(obj) or ""
    return doc.strip().splitlines()[0].strip() if doc.strip() else ""


def valid_parameters(factory: Callable) -> list[str] | None:
    """Names of the keyword parameters ``factory`` accepts.

    ``None`` means "anything" (the factory takes ``**kwargs`` and checks for
    itself).
    """
    if inspect.isclass(factory) and hasattr(factory, "_get_param_names"):
        return list(factory._get_param_names())
    target = factory.__init__ if inspect.isclass(factory) else factory
    params = inspect.signature(target).parameters.values()
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params):
        return None
    return [
        p.name
        for p in params
        if p.name != "self"
        and p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)
    ]


def check_parameters(what: str, given: Mapping[str, Any], valid: list[str]) -> None:
    """Raise :class:`InvalidParameterError` naming the valid parameters."""
    message = unknown_parameters(what, given, valid)
    if message is not None:
        raise InvalidParameterError(message)


class Registry:
    """A name -> component mapping with lazy built-ins and entry-point plugins.

    Parameters
    ----------
    kind : str
        What the registry holds, singular (``"clusterer"``); used in messages.
    group : str
        The entry-point group third-party packages advertise plugins in.
    builtins : mapping of str to str
        Built-in names and the ``"module:attribute"`` path of each.

    Examples
    --------
    >>> reg = Registry("widget", group="novelty.widgets")
    >>> @reg.register("square", description="A square widget.")
    ... def square(side=1.0):
    ...     return side * side
    >>> reg.make("square", side=3.0)
    9.0
    >>> "square" in reg
    True
    """

    def __init__(self, kind: str, group: str, builtins: Mapping[str, str] | None = None,
                 elsewhere: Mapping[str, str] | None = None):
        self.kind = kind
        self.group = group
        self._paths: dict[str, str] = dict(builtins or {})
        #: names used elsewhere that this registry does not hold, with where (said when one is asked for)
        self.elsewhere: Mapping[str, str] = MappingProxyType(dict(elsewhere or {}))
        self._loaded: dict[str, Any] = {}
        self._descriptions: dict[str, str] = {}
        self._plugins_read = False

    # ------------------------------------------------------------------ adding
    def register(
        self,
        name: str,
        obj: Any = None,
        *,
        description: str | None = None,
        replace: bool = False,
    ):
        """Register ``obj`` under ``name``; without ``obj``, return a decorator.

        A string ``obj`` is taken as a lazy ``"module:attribute"`` path.
        """
        if not isinstance(name, str) or not name or name != name.strip():
            raise RegistryError(f"A {self.kind} name must be a non-empty string; got {name!r}.")

        def add(target: Any) -> Any:
            self._read_plugins()
            if not replace and name in self:
                raise RegistryError(
                    f"A {self.kind} named '{name}' is already registered; "
                    "pass replace=True to replace it."
                )
            self._loaded.pop(name, None)
            self._paths.pop(name, None)
            if isinstance(target, str):
                self._paths[name] = target
            else:
                self._loaded[name] = target
            if description is not None:
                self._descriptions[name] = description
            else:
                self._descriptions.pop(name, None)
            return target

        return add if obj is None else add(obj)

    def unregister(self, name: str) -> None:
        """Remove ``name`` (mainly for tests and interactive sessions)."""
        self._check_known(name)
        self._loaded.pop(name, None)
        self._paths.pop(name, None)
        self._descriptions.pop(name, None)

    # ----------------------------------------------------------------- reading
    def __contains__(self, name: object) -> bool:
        self._read_plugins()
        return name in self._loaded or name in self._paths

    def names(self) -> list[str]:
        """Every registered name, sorted."""
        self._read_plugins()
        return sorted(set(self._loaded) | set(self._paths))

    def __iter__(self):
        return iter(self.names())

    def __len__(self) -> int:
        return len(self.names())

    def get(self, name: str) -> Any:
        """The class or factory registered as ``name`` (imported on first use)."""
        self._check_known(name)
        if name not in self._loaded:
            path = self._paths[name]
            module_name, _, attribute = path.partition(":")
            module = importlib.import_module(module_name)
            obj = module
            for part in attribute.split("."):
                obj = getattr(obj, part)
            self._loaded[name] = obj
        return self._loaded[name]

    def describe(self, name: str) -> str:
        """The one-line description of ``name``."""
        if name in self._descriptions:
            return self._descriptions[name]
        try:
            obj = self.get(name)
        except Exception as exc:  # one broken plugin must not hide the others
            return f"(cannot be loaded: {type(exc).__name__}: {exc})"
        return _first_line(obj)

    def descriptions(self) -> Mapping[str, str]:
        """A read-only ``{name: one-line description}`` view of the registry."""
        return MappingProxyType({name: self.describe(name) for name in self.names()})

    def parameters(self, name: str) -> list[str] | None:
        """The parameter names ``name`` takes (``None``: it checks for itself)."""
        return valid_parameters(self.get(name))

    def make(self, name: str, **params: Any) -> Any:
        """Build the component registered as ``name`` with ``params``."""
        factory = self.get(name)
        if inspect.isclass(factory) and hasattr(factory, "from_params"):
            return factory.from_params(**params)  # routes a flat parameter set itself
        valid = valid_parameters(factory)
        if valid is not None:
            check_parameters(f"{self.kind} '{name}'", params, valid)
        return factory(**params)

    def name_of(self, obj_or_class: Any) -> str | None:
        """The registered name of a class (or of an instance's class), if any."""
        cls = obj_or_class if inspect.isclass(obj_or_class) else type(obj_or_class)
        for name in self.names():
            try:
                if self.get(name) is cls:
                    return name
            except Exception:  # a broken plugin must not hide the others
                continue
        return None

    # ---------------------------------------------------------------- internal
    def _check_known(self, name: str) -> None:
        if name in self:
            return
        if name in self.elsewhere:
            raise UnknownNameError(f"{name!r} is not a registered {self.kind}: {self.elsewhere[name]}")
        known = self.names()
        close = difflib.get_close_matches(str(name), known, n=3, cutoff=0.5)
        hint = f" Did you mean {', '.join(repr(c) for c in close)}?" if close else ""
        raise UnknownNameError(
            f"Unknown {self.kind} {name!r}.{hint} Known {self.kind}s: {', '.join(known) or '(none)'}."
        )

    def _read_plugins(self) -> None:
        if self._plugins_read:
            return
        self._plugins_read = True
        for ep in entry_points(group=self.group):
            # Built-ins and run-time registrations win over plugins of the same name.
            if ep.name not in self._loaded and ep.name not in self._paths:
                self._paths[ep.name] = ep.value

    def __repr__(self) -> str:
        return f"Registry(kind={self.kind!r}, group={self.group!r}, names={self.names()})"


# ---------------------------------------------------------------------------
# The project's registries. Built-ins are imported on first use.

clusterers = Registry(
    "clusterer",
    group="novelty.clusterers",
    builtins={
        "som": "novelty.clusterers.som:SOM",
        "gng": "novelty.clusterers.gng:GrowingNeuralGas",
        "gwr": "novelty.clusterers.gwr:GrowWhenRequired",
        "online-kmeans": "novelty.clusterers.kmeans:OnlineKMeans",
        "world-cells": "novelty.maps.cells:WorldCells",
    },
)

synapses = Registry(
    "synapse",
    group="novelty.synapses",
    builtins={
        "stanley": "novelty.habituation.stanley:StanleySynapse",
        "wang-hsu": "novelty.habituation.wang_hsu:WangHsuSynapse",
        "staddon-higa": "novelty.habituation.staddon_higa:StaddonHigaSynapse",
    },
)

#: River's anomaly detectors (:mod:`novelty.bench.river`): names of the benchmark, not of this registry
RIVER_DETECTORS = ("river-hst", "river-loda", "river-lof")

detectors = Registry(
    "detector",
    group="novelty.detectors",
    elsewhere={name: ("one of River's anomaly detectors, which 'novelty bench' runs by name beside ours (extra "
                      "river: novelty bench --detector " + name + " ...); a model file holds arrays and JSON, "
                      "never a pickled River model, so no registry holds it.") for name in RIVER_DETECTORS},
    builtins={
        "habituating": "novelty.filter:HabituatingFilter",
        "hsom": "novelty.filter:hsom",
        "gwr-novelty": "novelty.presets:gwr_novelty",
        "gwr-explore": "novelty.presets:gwr_explore",
        "gwr-explore-wang-hsu": "novelty.presets:gwr_explore_wang_hsu",
        "gwr-explore-staddon-higa": "novelty.presets:gwr_explore_staddon_higa",
        "explore": "novelty.presets:explore",
        "gng-stanley": "novelty.presets:gng_stanley",
        "som-wang-hsu": "novelty.presets:som_wang_hsu",
        "gwr-wang-hsu": "novelty.presets:gwr_wang_hsu",
        "gng-wang-hsu": "novelty.presets:gng_wang_hsu",
        "hsom-mismatch": "novelty.presets:hsom_mismatch",
        "kmeans-stanley": "novelty.presets:kmeans_stanley",
        "cell-map": "novelty.maps.habituating_map:HabituatingMap",
        "habituating-map": "novelty.maps.habituating_map:habituating_map",
        "map-explore": "novelty.maps.habituating_map:map_explore",
        "kohonen-filter": "novelty.baselines.kohonen:KohonenNoveltyFilter",
        "autoencoder-filter": "novelty.baselines.autoencoder:AutoencoderFilter",
        "gmm": "novelty.baselines.gmm:GaussianMixtureDetector",
        "som-distance": "novelty.baselines.som_distance:SOMDistance",
        "nearest-memory": "novelty.baselines.nearest_memory:NearestMemory",
        "knn": "novelty.baselines.knn:KNNDetector",
        "occupancy-grid": "novelty.baselines.occupancy_grid:OccupancyGrid",
        "context": "novelty.context:SequenceContext",
        "parzen": "novelty.baselines.parzen:ParzenDetector",
        "isolation-forest": "novelty.baselines.sklearn_outlier:IsolationForestDetector",
        "one-class-svm": "novelty.baselines.sklearn_outlier:OneClassSVMDetector",
        "lof": "novelty.baselines.sklearn_outlier:LocalOutlierFactorDetector",
        "elliptic-envelope": "novelty.baselines.sklearn_outlier:EllipticEnvelopeDetector",
        "pyod": "novelty.baselines.pyod_outlier:PyODDetector",
    },
)

#: datasets and tasks (:mod:`novelty.datasets`); their built-ins are :data:`novelty.tasks.registered.TASKS`
datasets = Registry("dataset", group="novelty.datasets", builtins=TASKS)

#: the registries by the kind they hold
_BY_KIND = {r.kind: r for r in (detectors, clusterers, synapses, datasets)}
#: the kinds of component, singular: ``"detector"``, ``"clusterer"``, ``"synapse"``, ``"dataset"``
KINDS = tuple(_BY_KIND)


def of_kind(kind: str) -> Registry:
    """The registry of ``kind``: ``"detector"``, ``"clusterer"``, ``"synapse"`` or ``"dataset"``.

    >>> of_kind("synapse") is synapses
    True
    >>> of_kind("model")
    Traceback (most recent call last):
    ...
    novelty.registry.RegistryError: Unknown kind of component 'model'; expected 'detector', 'clusterer', 'synapse' or 'dataset'.
    """
    try:
        return _BY_KIND[kind]
    except (KeyError, TypeError):
        kinds = [repr(k) for k in KINDS]
        raise RegistryError(f"Unknown kind of component {kind!r}; expected {', '.join(kinds[:-1])} "
                            f"or {kinds[-1]}.") from None


def build(kind: str, spec: Any, **params: Any) -> Any:
    """A new component of ``kind`` from ``spec``, a registered name or an instance.

    A name is made by the registry of ``kind`` with ``params``; an instance
    is cloned (its parameters, never its learnt state) and then given
    ``params``, so that the caller's object is never changed.

    >>> som = build("clusterer", "som", n_rows=3)
    >>> som.n_rows, build("clusterer", som, n_columns=4).n_rows
    (3, 3)
    >>> build("clusterer", som) is som
    False
    """
    if isinstance(spec, str):
        return of_kind(kind).make(spec, **params)
    from sklearn.base import clone  # scikit-learn is heavy: kept out of ``import novelty``

    return clone(spec).set_params(**params)
