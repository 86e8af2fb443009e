"""Every example of the README, of the guide pages and of the studies' reports runs, as a user
would run it, and prints what its comments say.

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

What a block prints is compared with what the page says it prints
(``tests/printed.py`` gives the forms and the tolerance): a ``print`` line's
comment, comment lines below a ``print``, or a ``text`` block marked
``<!-- printed by the block above -->``. A Python block that prints more than
its comments speak for says why in ``<!-- output not checked: the reason -->``.
"""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from . import printed

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: the pages whose blocks run: the README, the guides and the studies' reports
PAGES = [ROOT / "README.md", DOCS / "index.md", *sorted((DOCS / "guide").rglob("*.md")),
         *sorted((ROOT / "studies").rglob("*.md"))]
#: a fenced block, with the HTML comment on the line before it, if any
FENCE = re.compile(r"(?:^<!-- (?P<note>[^\n]*?) -->\n(?:\n)?)?^```(?P<lang>[^\n`]*)\n(?P<code>.*?)^```\s*$",
                   flags=re.S | re.M)
#: the notes a block can carry: why it is not run, why its output is not checked, or that it is the
#: output of the block before it
NOTE = re.compile(r"(?P<kind>not run|output not checked): (?P<reason>.*)|(?P<output>printed by the block above)")
RUNNABLE = {"python", "bash"}
FILE_BLOCK = re.compile(r"# ([\w-]+\.py)\n")


def blocks(page: Path) -> list[dict]:
    """The page's fenced blocks (MyST directives such as ``{toctree}`` left out), in order.

    Each has its ``reason`` not to run, its ``unchecked`` reason (output not
    compared), and ``printed``: the text the page shows as its output, if any.
    """
    found = []
    for m in FENCE.finditer(page.read_text(encoding="utf-8")):
        if m["lang"].strip().startswith("{"):
            continue
        note = NOTE.fullmatch(m["note"] or "")
        if note and note["output"] and found:
            found[-1]["printed"] = m["code"]
            continue
        kind = note["kind"] if note else None
        found.append({"page": page, "index": len(found), "lang": m["lang"].strip(), "code": m["code"],
                      "reason": note["reason"] if kind == "not run" else None,
                      "unchecked": note["reason"] if kind == "output not checked" else None, "printed": None})
    return found


BLOCKS = [b for page in PAGES for b in blocks(page)]


def block_id(b) -> str:
    return f"{b['page'].relative_to(ROOT)}[{b['index']}:{b['lang']}]"


RUN = [b for b in BLOCKS if b["reason"] is None and b["lang"] in RUNNABLE]
NOT_RUN = [b for b in BLOCKS if b["reason"] is not None]


def test_every_block_runs_or_says_why_not():
    unmarked = [block_id(b) for b in BLOCKS if b["reason"] is None and b["lang"] not in RUNNABLE]
    assert not unmarked, f"blocks neither runnable nor marked '<!-- not run: reason -->': {unmarked}"
    assert len(RUN) >= 10, [block_id(b) for b in RUN]


def test_blocks_not_run_or_not_checked_and_why():
    # The list a reader of the test output sees; every reason is a sentence, not a bare marker.
    for b in BLOCKS:
        for kind in ("reason", "unchecked"):
            if b[kind] is not None:
                print(f"{block_id(b)}: {'not run' if kind == 'reason' else 'output not checked'}: {b[kind]}")
                assert len(b[kind].split()) >= 3, block_id(b)


@pytest.mark.parametrize("block", [b for b in RUN if b["lang"] == "python"], ids=block_id)
def test_no_value_is_stated_where_nothing_prints_it(block):
    # "x.mean()  # 0.5" states an output no test can compare; "print(x.mean())  # 0.5" is compared
    stated = printed.unprinted_values(block["code"])
    assert not stated, f"{block_id(block)}: print these, so that the docs test compares them: {stated}"


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


def run_block(block: dict, where: Path, env: dict) -> subprocess.CompletedProcess:
    """Run ``block`` in ``where``; a Python block's prints are recorded by line (``done.said``)."""
    for other in blocks(block["page"]):  # the page's files, importable by its blocks
        if other["lang"] == "python" and (m := FILE_BLOCK.match(other["code"])):
            (where / m.group(1)).write_text(other["code"], encoding="utf-8")
    if block["lang"] == "python":
        aside = where.parent / f"{where.name}-bin"  # beside the folder, so the block's own files are alone
        code, record = aside / "block.py", aside / "said.json"
        code.write_text(block["code"], encoding="utf-8")
        command = [sys.executable, "-c", printed.WRAPPER, str(code), str(record)]
    else:
        command = ["bash", "-e", "-o", "pipefail", "-c", block["code"]]
    done = subprocess.run(command, cwd=where, env=env, capture_output=True, text=True, timeout=600)
    done.said = json.loads(record.read_text()) if block["lang"] == "python" and record.exists() else []
    return done


def output_problems(block: dict, done: subprocess.CompletedProcess) -> list[str]:
    """Where what ``block`` printed and what its page says it printed disagree."""
    problems = []
    if block["printed"] is not None and printed.differs_by_line(block["printed"], done.stdout):
        problems.append(f"the block printed\n{done.stdout}\nwhere the page shows\n{block['printed']}")
    if block["lang"] == "python" and block["unchecked"] is None:
        wrong, unclaimed = printed.misstatements(block["code"], done.said)
        problems += wrong
        if unclaimed.strip() and block["printed"] is None:
            problems.append(f"it printed {unclaimed!r}, which no comment states; show it (a comment or a "
                            "'printed by the block above' block) or say '<!-- output not checked: why -->'")
    return problems


@pytest.mark.slow
@pytest.mark.parametrize("block", RUN, ids=block_id)
def test_block_runs_as_written_and_prints_what_it_says(block, folder):
    where, env = folder
    done = run_block(block, where, env)
    assert done.returncode == 0, f"{block_id(block)} failed:\n{block['code']}\n--- stderr:\n{done.stderr[-3000:]}"
    problems = output_problems(block, done)
    assert not problems, f"{block_id(block)}:\n" + "\n".join(problems)


@pytest.mark.slow
def test_a_comment_that_misstates_the_output_fails(folder):
    # The first block of the streaming guide, its comment made wrong as it once was: the test sees it.
    block = next(b for b in RUN if b["page"].name == "streaming.md")
    line = next(line for line in block["code"].splitlines() if line.startswith("print("))
    broken = {**block, "code": block["code"].replace(line, line.split("#")[0] + "# 1.0: a first perception")}
    done = run_block(broken, *folder)
    assert done.returncode == 0
    problems = output_problems(broken, done)
    assert len(problems) == 1 and "the comment says '1.0: a first perception'" in problems[0], problems
    assert not output_problems(block, done)  # the page as written states what this run printed


def test_every_guide_page_is_in_the_site():
    # A page missing from every toctree is a Sphinx warning, which fails the build.
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    for page in sorted(DOCS.rglob("*.md")):
        rel = page.relative_to(DOCS).with_suffix("").as_posix()
        if rel in ("index", "api", "readme") or rel.startswith(("reproduction/", "api/", "_build/", "cli/")):
            continue
        assert re.search(rf"^{re.escape(rel)}$", index, flags=re.M), f"{rel} is not in docs/index.md"
