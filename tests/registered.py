"""Every registered detector as a test parameter.

A detector whose optional dependency is not installed (its ``requires``, such
as PyOD for ``pyod``) is still listed, and skipped with the extra that
installs it, so a run without it says what was left out and why.
"""

import importlib.util

import pytest

from novelty.registry import detectors

#: the extra of pyproject.toml that installs each optional dependency
EXTRAS = {"pyod": "pyod", "river": "river"}


def missing_requirements(name: str) -> list[str]:
    """The optional modules detector ``name`` needs that are not installed."""
    return [m for m in getattr(detectors.make(name), "requires", ()) if importlib.util.find_spec(m) is None]


def detector_params(names=None) -> list:
    """``pytest.param(name)`` for every registered detector, marked skip when its dependency is missing."""
    params = []
    for name in detectors.names() if names is None else names:
        missing = missing_requirements(name)
        extras = ",".join(EXTRAS.get(m, m) for m in missing)
        marks = [pytest.mark.skip(reason=f"the {name!r} detector needs {', '.join(missing)}, not installed "
                                         f"(pip install 'novelty-habituation[{extras}]')")] if missing else []
        params.append(pytest.param(name, marks=marks, id=name))
    return params
