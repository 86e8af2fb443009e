"""Messages shared by the registry and the checks, in a module of the standard library only.

``import novelty`` loads the registry, which must not pull in numpy; the
checks of :mod:`novelty._validation` need numpy. The refusal of unknown
parameter names is worded once, here, for both.
"""

from __future__ import annotations

import difflib

__all__ = ["unknown_parameters"]


def unknown_parameters(what: str, given, valid) -> str | None:
    """The message refusing the names of ``given`` that are not in ``valid`` (a close one suggested); None if none.

    >>> unknown_parameters("Reading", {"sector": 8}, ["sectors", "topic"])
    "Unknown parameter 'sector' (did you mean 'sectors'?) for Reading. Valid parameters: sectors, topic."
    """
    unknown = [name for name in given if name not in valid]
    if not unknown:
        return None
    hints = []
    for name in unknown:
        close = difflib.get_close_matches(name, valid, n=1)
        hints.append(f"'{name}'" + (f" (did you mean '{close[0]}'?)" if close else ""))
    return (f"Unknown parameter{'s' if len(unknown) > 1 else ''} {', '.join(hints)} for {what}. "
            f"Valid parameters: {', '.join(sorted(valid)) or '(none)'}.")
