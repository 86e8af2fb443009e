"""Fill the generated blocks of a report (``docs/reproduction.md``) with the experiments' tables.

A block is everything between ``<!-- BEGIN generated: KEY -->`` and
``<!-- END generated: KEY -->``; the text around the blocks is the report's
own and is kept as it is. Every block named in the report must be given, so
a report never keeps a stale table silently.
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["fill", "fill_file"]

_BLOCK = re.compile(r"(<!-- BEGIN generated: (?P<key>[\w-]+) -->\n)(?P<body>.*?)(<!-- END generated: (?P=key) -->)",
                    re.DOTALL)


def fill(text: str, blocks: dict[str, str], partial: bool = False) -> str:
    """``text`` with each generated block's body replaced by ``blocks[key]``.

    With ``partial``, blocks not in ``blocks`` keep their body (one
    experiment rerun); otherwise a block without new content is an error.

    >>> fill("a\\n<!-- BEGIN generated: x -->\\nold\\n<!-- END generated: x -->\\nb", {"x": "new\\n"})
    'a\\n<!-- BEGIN generated: x -->\\nnew\\n<!-- END generated: x -->\\nb'
    """
    missing = [m["key"] for m in _BLOCK.finditer(text) if m["key"] not in blocks]
    if missing and not partial:
        raise ValueError(f"No content for the generated blocks {missing}; given: {sorted(blocks)}.")

    def body(match: re.Match) -> str:
        new = blocks.get(match["key"], match["body"])
        return match.group(1) + new.rstrip("\n") + "\n" + match.group(4)

    return _BLOCK.sub(body, text)


def fill_file(path, blocks: dict[str, str], partial: bool = False) -> Path:
    """Fill the generated blocks of the report at ``path`` in place."""
    path = Path(path)
    path.write_text(fill(path.read_text(encoding="utf-8"), blocks, partial), encoding="utf-8")
    return path
