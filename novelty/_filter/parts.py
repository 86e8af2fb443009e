"""The parts' parameters after fitting: learning on is refused while they differ from the fitted.

A filter's ``clusterer`` and ``synapse`` parameters are templates: ``fit``
builds ``clusterer_`` and ``synapse_`` from them. Set after fitting
(``set_params(synapse__alpha=1.5)``, a new ``clusterer``, or an attribute set
on a template; never on a fitted part, whose one writer is the engine:
:meth:`novelty._component.Component.__setattr__`), they take effect at the
next ``fit``:
learning on (``stream``, ``partial_fit``, ``learn_one``) is refused until the
model is refitted or the values are set back, so that no scan is learned
under parameters other than those it reports. Scoring reads the fitted state.

Noticing a change costs one comparison of counts of changes
(:meth:`novelty._component.Component.__setattr__`) per learning call; the
parameters are compared only when a count moved. The bookkeeping lives in the
filter's ``__dict__`` (``_parts_changed``, ``_parts_seen``), written without
counting as a change of the filter.
"""

from __future__ import annotations

from ..registry import build
from . import efficacy_range

__all__ = ["check_online", "note", "record"]


def note(detector) -> None:
    """After ``set_params``: record which fitted parts' parameters differ now."""
    if detector._is_fitted():
        vars(detector)["_parts_changed"] = changed(detector)


def record(detector) -> None:
    """After a fit or a load: the parts as they are now are the ones checked."""
    vars(detector)["_parts_changed"] = changed(detector)  # a file saved after set_params
    vars(detector)["_parts_seen"] = _counts(detector)


def check_online(detector) -> None:
    """Refuse to learn on after a part's parameters changed (module docstring), noticing also
    those set directly on the parts since the last call: on ``clusterer`` or ``synapse`` as
    ``set_params`` notes them, on the fitted ``clusterer_`` or ``synapse_`` checked against
    their rules (and then used)."""
    counts = _counts(detector)
    seen = vars(detector).get("_parts_seen")
    if counts != seen:
        if seen is None or counts[2:] != seen[2:]:
            detector.clusterer_._validate_params()
            detector.synapse_._validate_params()
            efficacy_range.check(detector.synapse_, detector.stimulus)
        if seen is None or counts[:2] != seen[:2]:
            vars(detector)["_parts_changed"] = changed(detector)
    names = vars(detector).get("_parts_changed")
    if names:
        detector._validate_params()  # a value that is wrong anyway is named as such first
        raise ValueError(
            f"{', '.join(names)} changed after fitting; the fitted clusterer_ and synapse_ keep the "
            "values they learned with, so learning on would mix the two. Refit (fit) to learn with the "
            "new values, or set them back."
        )
    if counts != seen:
        vars(detector)["_parts_seen"] = counts


def templates(detector) -> tuple:
    """The unfitted parts that are components (a part given by name has nothing to watch:
    replacing it is a change of the filter)."""
    return tuple(p for p in (detector.clusterer, detector.synapse) if hasattr(p, "get_params"))


def changed(detector) -> list[str]:
    """The parameters of the parts that differ from those the fitted parts learned with."""
    out = []
    for part in ("clusterer", "synapse"):
        spec, fitted = getattr(detector, part), getattr(detector, f"{part}_")
        template = build(part, spec) if isinstance(spec, str) else spec
        if type(template) is not type(fitted):
            out.append(part)
            continue
        ours, theirs = template.get_params(deep=False), fitted.get_params(deep=False)
        out += [f"{part}__{k}" for k in ours if repr(ours[k]) != repr(theirs.get(k))]
    return out


def _counts(detector) -> tuple:
    """How many times attributes were set on the parts, templates and fitted ones."""
    return (getattr(detector.clusterer, "_changes", 0), getattr(detector.synapse, "_changes", 0),
            detector.clusterer_._changes, detector.synapse_._changes)
