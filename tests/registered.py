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


def reads_a_layout(name: str) -> bool:
    """Whether detector ``name`` reads rows of a layout of its own (``input_layout``: e.g. the points input)."""
    return getattr(detectors.make(name), "input_layout", None) is not None


def detector_params(names=None, *, any_rows: bool = False) -> list:
    """``pytest.param(name)`` for every registered detector, marked skip when its dependency is missing.

    ``any_rows=True``: the test feeds rows of any width or dict scans of its own, which a detector
    that reads a layout of its own refuses by design; such a detector is marked skip, saying where
    its own checks are (the conformance checks with its example rows, and its test file).
    """
    params = []
    for name in detectors.names() if names is None else names:
        missing = missing_requirements(name)
        extras = ",".join(EXTRAS.get(m, m) for m in missing)
        marks = [pytest.mark.skip(reason=f"the {name!r} detector needs {', '.join(missing)}, not installed "
                                         f"(pip install 'novelty-habituation[{extras}]')")] if missing else []
        if any_rows and not missing and reads_a_layout(name):
            marks = [pytest.mark.skip(reason=f"the {name!r} detector reads rows of its own layout and refuses "
                                             "others; the conformance checks run it on its example rows")]
        params.append(pytest.param(name, marks=marks, id=name))
    return params
