"""Short parameter names: which of a filter's parts takes ``alpha``, ``learning_rate``, ...

:func:`novelty.make` and :meth:`HabituatingFilter.from_params
<novelty.filter.HabituatingFilter.from_params>` take one flat set of
parameters; each goes to whichever of the filter, its clusterer or its
synapse takes it, and ``clusterer__name`` / ``synapse__name`` settle a name
both parts take. :meth:`~novelty.filter.HabituatingFilter.set_params` routes
short names the same way (:func:`full_names`), so that a grid search over
``{"alpha": [...]}`` searches the synapse.
"""

from __future__ import annotations

import difflib

from ..registry import InvalidParameterError, build, check_parameters, of_kind

__all__ = ["route", "full_names"]

PARTS = ("clusterer", "synapse")


def route(own_names: list[str], clusterer, synapse, params: dict) -> tuple[dict, dict]:
    """``(the filter's own parameters, {part: the part built with its parameters})`` from one
    flat set (unknown or ambiguous names are refused with the valid ones listed)."""
    params = dict(params)
    own = {k: params.pop(k) for k in list(params) if k in own_names}
    parts = {"clusterer": clusterer, "synapse": synapse}
    routed: dict[str, dict] = {"clusterer": {}, "synapse": {}}
    valid = {part: parameters_of(part, spec) for part, spec in parts.items()}
    for key, value in params.items():
        part, _, name = key.partition("__")
        if name and part in routed:
            check_parameters(f"{part} {parts[part]!r}", {name: value}, valid[part])
            routed[part][name] = value
            continue
        taker = _taker(key, valid)
        if taker is None:
            all_valid = own_names + [n for p in routed for n in valid[p]]
            check_parameters("the habituating filter", {key: value}, all_valid)
        routed[taker][key] = value
    return own, {part: build(part, spec, **routed[part]) for part, spec in parts.items()}


def full_names(owner: str, own_names: list[str], parts: dict, params: dict) -> dict:
    """``params`` with every short name of a part's parameter written in full
    (``alpha`` -> ``synapse__alpha``), as ``set_params`` takes them; ``parts`` the filter's
    ``clusterer`` and ``synapse`` (a part given in the same call is the one a name goes to)."""
    short = [key for key in params if key not in own_names and "__" not in key]
    if not short:
        return params
    # a value that is not a part yet (checked in fit, as every parameter) takes no short name
    valid = {part: parameters_of(part, spec, strict=False) for part, spec in parts.items()}
    full = {key: value for key, value in params.items() if key not in short}
    for key in short:
        try:
            taker = _taker(key, valid)
        except InvalidParameterError as exc:
            raise ValueError(str(exc)) from None
        if taker is None:
            raise ValueError(_unknown(owner, key, own_names, valid))
        if isinstance(parts[taker], str):
            raise ValueError(f"'{key}' is a parameter of the {taker} {parts[taker]!r}, given by name; "
                             f"set {taker}= to an instance (novelty.make builds one) to set it.")
        full[f"{taker}__{key}"] = params[key]
    return full


def parameters_of(part: str, spec, strict: bool = True) -> list[str]:
    """The parameter names of a clusterer or synapse, given by its registered name or as an instance.

    Not ``strict``: anything else (an unknown name, a value that is no
    component) takes no parameter, rather than raising.
    """
    if isinstance(spec, str):
        if not strict and spec not in of_kind(part):
            return []
        return of_kind(part).parameters(spec) or []
    if not strict and not hasattr(spec, "get_params"):
        return []
    return list(spec.get_params(deep=False))


def _taker(key: str, valid: dict[str, list[str]]) -> str | None:
    """Which part (``"clusterer"`` or ``"synapse"``) takes the short name ``key``; None if neither."""
    takers = [part for part in valid if key in valid[part]]
    if len(takers) > 1:
        raise InvalidParameterError(
            f"Parameter '{key}' is taken by both the clusterer and the synapse; "
            f"write clusterer__{key} or synapse__{key}."
        )
    return takers[0] if takers else None


def _unknown(owner: str, key: str, own: list[str], valid: dict[str, list[str]]) -> str:
    """The message for a name neither the filter nor a part takes: the full names listed."""
    short = {name: f"{part}__{name}" for part, names in valid.items() for name in names}
    close = difflib.get_close_matches(key, own + list(short), n=1)
    hint = ""
    if close:
        hint = f" (did you mean '{close[0]}'" + (f", that is '{short[close[0]]}'" if close[0] in short else "") + "?)"
    settable = sorted(own + list(short.values()))
    return f"Unknown parameter '{key}'{hint} for {owner}. Valid parameters: {', '.join(settable)}."
