"""Docstring markup as plain text: roles and literals become what they name."""

import pytest

import novelty
from novelty._markup import plain_text


@pytest.mark.parametrize("text, plain", [
    ("Inspection task (see :func:`inspection`).", "Inspection task (see inspection)."),
    (":class:`~novelty.sonar.Robot` and :class:`novelty.sonar.Robot`", "Robot and novelty.sonar.Robot"),
    (":py:meth:`the fit method <novelty.Detector.fit>`", "the fit method"),
    ("``gwr-explore`` with `radius`", "gwr-explore with radius"),
    ("tau dy/dt = alpha (y0 - y) - S: no markup", "tau dy/dt = alpha (y0 - y) - S: no markup"),
])
def test_plain_text(text, plain):
    assert plain_text(text) == plain


def test_available_descriptions_are_plain_text():
    marked = {f"{kind}/{name}": text for kind, names in novelty.available().items()
              for name, text in names.items() if "`" in text or ":func:" in text or ":class:" in text}
    assert not marked
    assert novelty.available("detectors")["gwr-explore-wang-hsu"].startswith("gwr-explore with Wang-Hsu")
    assert "see :func:" not in novelty.datasets.available()["inspection-easy"]
