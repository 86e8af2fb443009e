"""Text for what a terminal or a Python prompt shows: docstring markup as plain text, a count with its noun."""

from __future__ import annotations

import re

__all__ = ["plain_text", "plain_descriptions", "counted"]

#: a Sphinx role (:func:`~novelty.x.name`, :py:class:`Title <target>`) or a literal (``name``, `name`)
_MARKUP = re.compile(r":[a-z]+(?::[a-z]+)?:`(~?)([^`<]*?)(?:\s*<[^>]*>)?`|``([^`]+)``|`([^`]+)`")


def plain_text(text: str) -> str:
    """reStructuredText roles and literals become their text; the rest is unchanged.

    A role shows its target (the last dotted part after ``~``, the title when
    one is given), a literal its content.

    >>> plain_text("see :func:`inspection`, :class:`~novelty.sonar.Robot`, ``x=1`` and `radius`")
    'see inspection, Robot, x=1 and radius'
    """
    def text_of(match: re.Match) -> str:
        tilde, target, literal, quoted = match.groups()
        if target is not None:
            return target.rsplit(".", 1)[-1] if tilde else target
        return literal if literal is not None else quoted

    return _MARKUP.sub(text_of, text)


def plain_descriptions(registry) -> dict:
    """``{name: description}`` of a registry, in plain text (a description is a docstring's first line)."""
    return {name: plain_text(text) for name, text in registry.descriptions().items()}


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and the noun, singular for one.

    >>> counted(1, "task"), counted(2, "task"), counted(0, "cell"), counted(3, "fix", "fixes")
    ('1 task', '2 tasks', '0 cells', '3 fixes')
    """
    return f"{n} {noun if n == 1 else plural or noun + 's'}"
