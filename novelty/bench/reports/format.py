"""How every report of the harness writes numbers and tables: one place, one style.

A markdown table with aligned columns (:func:`format_table`, readable as plain
text in a terminal too), numbers to a fixed number of decimals
(:func:`number`), a mean with its spread (:func:`mean_spread`), a signed
difference (:func:`signed`) and a p-value (:func:`p_value`, :func:`p_is`).
Missing values (``None``, NaN) are written ``-``.

>>> print(format_table(["detector", "AUC"], [["hsom", number(0.8123)]]))
| detector | AUC   |
|----------|-------|
| hsom     | 0.812 |
"""

from __future__ import annotations

import math
from typing import Sequence

__all__ = ["format_table", "escape", "number", "mean_spread", "signed", "p_value", "p_is", "yes_no", "MISSING"]

#: how a missing value is written
MISSING = "-"


def _missing(value) -> bool:
    return value is None or (isinstance(value, float) and math.isnan(value))


def number(value, digits: int = 3) -> str:
    """``value`` to ``digits`` decimals; large values with fewer (1,234 and 123.4); ``-`` if missing.

    >>> number(0.12345), number(123.45), number(12345.6), number(float("nan")), number(7)
    ('0.123', '123.5', '12,346', '-', '7')
    """
    if _missing(value):
        return MISSING
    if isinstance(value, int):
        return str(value)
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    if abs(value) >= 100:
        return f"{value:.1f}"
    return f"{value:.{digits}f}"


def mean_spread(mean: float, spread: float, digits: int = 3) -> str:
    """``"0.812 ± 0.030"``; the mean alone when the spread is missing.

    >>> mean_spread(0.8123, 0.03), mean_spread(0.8123, float("nan"))
    ('0.812 ± 0.030', '0.812')
    """
    return number(mean, digits) + ("" if _missing(spread) else f" ± {number(spread, digits)}")


def signed(mean: float, spread: float = float("nan")) -> str:
    """A difference with its sign, and its spread if there is one: ``"+0.012 ± 0.004"``.

    >>> signed(0.0123, 0.004), signed(-0.5)
    ('+0.012 ± 0.004', '-0.500')
    """
    if _missing(mean):
        return MISSING
    return f"{mean:+.3f}" + ("" if _missing(spread) else f" ± {spread:.3f}")


def p_value(value: float) -> str:
    """A p-value to three decimals, ``< 0.001`` below that, ``-`` if missing.

    >>> p_value(0.04321), p_value(1e-5)
    ('0.043', '< 0.001')
    """
    if _missing(value):
        return MISSING
    return "< 0.001" if value < 0.001 else f"{value:.3f}"


def p_is(value: float) -> str:
    """``"p = 0.043"`` or ``"p < 0.001"``.

    >>> p_is(0.04321), p_is(1e-5)
    ('p = 0.043', 'p < 0.001')
    """
    text = p_value(value)
    return f"p {text}" if text.startswith("<") else f"p = {text}"


def yes_no(flag: bool) -> str:
    """``"yes"`` or ``"no"``."""
    return "yes" if flag else "no"


def escape(text: str) -> str:
    r"""``text`` safe in a markdown table and a generated region: ``|`` escaped, comment markers and line breaks defused.

    A label is the user's text: a ``|`` would split its cell, a ``-->`` or
    ``<!--`` would end or open an HTML comment (the markers of a generated
    region in the documents), a line break would end its row.

    >>> print(escape("a|b <!-- end generated -->"))
    a\|b &lt;!-- end generated --&gt;
    """
    text = " ".join(str(text).splitlines())
    return text.replace("|", "\\|").replace("<!--", "&lt;!--").replace("-->", "--&gt;")


def format_table(header: Sequence[str], body: Sequence[Sequence[str]]) -> str:
    """A markdown table with aligned columns (readable as plain text too); every cell :func:`escape`-d."""
    header = [escape(h) for h in header]
    body = [[escape(c) for c in row] for row in body]
    widths = [max(len(h), *(len(r[i]) for r in body)) if body else len(h) for i, h in enumerate(header)]
    line = lambda cells: "| " + " | ".join(c.ljust(w) for c, w in zip(cells, widths)) + " |"  # noqa: E731
    rule = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    return "\n".join([line(header), rule, *(line(r) for r in body)])
