"""Every example of the README and of the guide pages runs, as a user would run it.

Each fenced block is run in a fresh interpreter (``python -c``) or shell
(``bash``), in a temporary folder holding a copy of ``examples/``, with only the
imports written in the block; ``novelty`` on the shell's path is this checkout's
command line. A Python block whose first line is a file name (``# fading.py``)
is a file of the page: it is written into the folder before the page's other
blocks run, so they can import it. A block that cannot run (a long benchmark, a
fragment of a configuration file, a live sensor) says so in an HTML comment on
the line before it, ``<!-- not run: the reason -->``, and is listed here with
its reason. The site itself (``docs/conf.py``) is built with warnings as errors
by CI.
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = [ROOT / "README.md", DOCS / "index.md", *sorted((DOCS / "guide").rglob("*.md"))]
FENCE = re.compile(r"(?:^<!-- not run: (?P<reason>.*?) -->\n(?:\n)?)?^```(?P<lang>[^\n`]*)\n(?P<code>.*?)^```\s*$",
                   flags=re.S | re.M)
RUNNABLE = {"python", "bash"}
FILE_BLOCK = re.compile(r"# ([\w-]+\.py)\n")


def blocks(page: Path) -> list[dict]:
    """The page's fenced blocks (MyST directives such as ``{toctree}`` left out), in order."""
    return [{"page": page, "index": i, "lang": m["lang"].strip(), "code": m["code"], "reason": m["reason"]}
            for i, m in enumerate(m for m in FENCE.finditer(page.read_text(encoding="utf-8"))
                                  if not m["lang"].strip().startswith("{"))]


BLOCKS = [b for page in PAGES for b in blocks(page)]


def block_id(b) -> str:
    return f"{b['page'].relative_to(ROOT)}[{b['index']}:{b['lang']}]"


RUN = [b for b in BLOCKS if b["reason"] is None and b["lang"] in RUNNABLE]
NOT_RUN = [b for b in BLOCKS if b["reason"] is not None]


def test_every_block_runs_or_says_why_not():
    unmarked = [block_id(b) for b in BLOCKS if b["reason"] is None and b["lang"] not in RUNNABLE]
    assert not unmarked, f"blocks neither runnable nor marked '<!-- not run: reason -->': {unmarked}"
    assert len(RUN) >= 10, [block_id(b) for b in RUN]


def test_blocks_not_run_and_why():
    # The list a reader of the test output sees; every reason is a sentence, not a bare marker.
    for b in NOT_RUN:
        print(f"{block_id(b)}: {b['reason']}")
        assert len(b["reason"].split()) >= 3, block_id(b)


@pytest.fixture
def folder(tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "build"))
    bin_dir = tmp_path.parent / f"{tmp_path.name}-bin"
    bin_dir.mkdir()
    shim = bin_dir / "novelty"  # the command a user's install puts on the path, for this checkout
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m novelty.cli "$@"\n')
    shim.chmod(0o755)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)]),
           "PATH": os.pathsep.join([str(bin_dir), str(Path(sys.executable).parent), os.environ.get("PATH", "")]),
           "MPLBACKEND": "Agg"}
    return tmp_path, env


@pytest.mark.parametrize("block", RUN, ids=block_id)
def test_block_runs_as_written(block, folder):
    where, env = folder
    for other in blocks(block["page"]):  # the page's files, importable by its blocks
        if other["lang"] == "python" and (m := FILE_BLOCK.match(other["code"])):
            (where / m.group(1)).write_text(other["code"], encoding="utf-8")
    command = [sys.executable, "-c", block["code"]] if block["lang"] == "python" else \
        ["bash", "-e", "-o", "pipefail", "-c", block["code"]]
    done = subprocess.run(command, cwd=where, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{block_id(block)} failed:\n{block['code']}\n--- stderr:\n{done.stderr[-3000:]}"


def test_every_guide_page_is_in_the_site():
    # A page missing from every toctree is a Sphinx warning, which fails the build.
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    for page in sorted(DOCS.rglob("*.md")):
        rel = page.relative_to(DOCS).with_suffix("").as_posix()
        if rel in ("index", "api", "readme") or rel.startswith(("reproduction/", "api/", "_build/", "cli/")):
            continue
        assert re.search(rf"^{re.escape(rel)}$", index, flags=re.M), f"{rel} is not in docs/index.md"
