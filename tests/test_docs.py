"""The documentation site's pages: their Python examples run as written.

The site itself (``docs/conf.py``) is built with warnings as errors by CI;
here every ``python`` block of the user guide pages in ``docs/`` is executed.
"""

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
PAGES = sorted(DOCS.glob("*.md")) + sorted(DOCS.glob("guide/*.md"))
BLOCKS = [(page.relative_to(DOCS).as_posix(), i, code) for page in PAGES
          for i, code in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), flags=re.S))]


def test_the_guide_has_examples():
    assert any(name == "index.md" for name, _, _ in BLOCKS)


@pytest.mark.parametrize("page, index, code", BLOCKS, ids=[f"{n}[{i}]" for n, i, _ in BLOCKS])
def test_docs_python_block_runs(page, index, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # examples may write files
    exec(compile(code, f"docs/{page}[python block {index}]", "exec"), {})


def test_every_page_is_in_the_site():
    # A page missing from every toctree is a Sphinx warning, which fails the build.
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    for page in PAGES:
        name = page.relative_to(DOCS).with_suffix("").as_posix()   # guide pages: guide/<page>
        if name not in ("index", "api", "readme"):
            assert re.search(rf"^{re.escape(name)}$", index, flags=re.M), f"{name}.md is not in docs/index.md"
