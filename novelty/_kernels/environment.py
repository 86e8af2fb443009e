"""``NOVELTY_NO_KERNELS``: whether the reference loops are asked for, read cheaply on every call."""

from __future__ import annotations

import os

__all__ = ["disabled"]


def _own_mapping(environ):
    """``environ``'s private mapping of encoded names to encoded values (CPython's
    ``os.environ._data``), when it holds exactly what ``environ`` shows; else None.

    :func:`disabled` is read on every learning call, where ``os.environ.get`` of a missing
    variable raises and catches a KeyError: a single scan's ``score_learn_one`` was measurably
    slower that way than through the mapping (docs/guide/performance.md).
    Checked once, here; anything else (another Python, another layout) reads ``os.environ``.
    """
    data = getattr(environ, "_data", None)
    try:
        if not isinstance(data, dict) or len(data) != len(environ):
            return None
        for name, value in environ.items():
            if environ.decodevalue(data[environ.encodekey(name)]) != value:
                return None
    except (AttributeError, KeyError, TypeError, ValueError):
        return None
    return data


#: the environment's own mapping, and the variable's key in it (see :func:`_own_mapping`)
_ENVIRON = _own_mapping(os.environ)
_KEY = os.environ.encodekey("NOVELTY_NO_KERNELS") if _ENVIRON is not None else None


def disabled() -> bool:
    """Whether ``NOVELTY_NO_KERNELS`` asks for the reference loops."""
    if _ENVIRON is not None:
        value = _ENVIRON.get(_KEY)
        return value is not None and os.environ.decodevalue(value) not in ("", "0")
    return os.environ.get("NOVELTY_NO_KERNELS", "") not in ("", "0")
