"""The repository's layout: what a reader of the code meets.

- No tracker numbers ("issue 7", "#12") in code, tests, docs or benchmarks: a
  reader of the code cannot follow them.
- No import cycle among novelty's modules, counting the imports inside
  functions too, and none among its subpackages.
"""

import ast
import re
from pathlib import Path

import pytest

import novelty

ROOT = Path(novelty.__file__).resolve().parents[1]
PACKAGE = ROOT / "novelty"

# "issue 7", "issues #7", "PR 12", "gh-12", "#12"; not a colour ("#d62728", "#222222")
TRACKER = re.compile(r"\b(?:issue|pull request|PR|ticket)s?\s*#?\s*\d+|(?<![\w&#/])#\d{1,5}(?![0-9a-fA-F])|\bgh-\d+",
                     re.IGNORECASE)
TEXT = {".py", ".md", ".toml", ".txt", ".rst", ".cfg", ".yml", ".yaml"}


def _text_files():
    for top in ("novelty", "tests", "docs", "benchmarks", "examples"):
        for path in sorted((ROOT / top).rglob("*")):
            rel = path.relative_to(ROOT).parts
            if path.suffix in TEXT and not {"_build", "__pycache__"} & set(rel) and rel[:2] != ("docs", "api"):
                yield path
    yield ROOT / "README.md"


@pytest.mark.parametrize("text, found", [
    ("see issue 7", "issue 7"), ("Issues #12 and", "Issues #12"), ("PR 3", "PR 3"), ("(#45)", "#45"),
    ("gh-101", "gh-101"), ('colour "#d62728"', None), ('"#222222"', None), ("x = 3  # 10 scans", None),
    ("tissue 7", None),
])
def test_the_tracker_pattern(text, found):
    match = TRACKER.search(text)
    assert (match.group(0) if match else None) == found


def test_no_tracker_numbers():
    hits = [f"{path.relative_to(ROOT)}:{i}: {line.strip()}"
            for path in _text_files() if path.is_file()
            for i, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1)
            if TRACKER.search(line) and path != Path(__file__).resolve()]  # this file shows examples
    assert not hits, "tracker numbers mean nothing to a reader of the code:\n" + "\n".join(hits)
