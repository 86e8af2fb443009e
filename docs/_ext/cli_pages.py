"""A page per command of the ``novelty`` command line, generated from its ``--help``.

At the start of every build, ``docs/cli/<command>.md`` is written from the
parser the command line itself builds (:func:`novelty.cli.build_parser`), so a
page cannot drift from what ``novelty <command> --help`` prints. The pages are
build products, like the API reference, and not kept in the repository;
``docs/cli/index.md`` lists them.
"""

import argparse
import os
from pathlib import Path

from novelty.cli import build_parser

#: the width --help is formatted to on the pages: it fits the theme's code column
WIDTH = 88


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:  # argparse keeps the sub-commands on their action only
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _summaries(parser: argparse.ArgumentParser) -> dict[str, str]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return {a.dest: a.help or "" for a in action._choices_actions}
    return {}


def write_pages(folder: Path) -> list[str]:
    """Write one page per command into ``folder``; return the command names."""
    before = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(WIDTH)  # argparse reads the width from COLUMNS
    try:
        parser = build_parser()
        commands, summaries = _subparsers(parser), _summaries(parser)
        pages = {"novelty": ("novelty", "the command line", parser.format_help())}
        pages.update({name: (f"novelty {name}", summaries.get(name, ""), sub.format_help())
                      for name, sub in commands.items()})
    finally:
        if before is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = before
    folder.mkdir(exist_ok=True)
    for name, (title, summary, text) in pages.items():
        page = f"# `{title}`\n\n{summary[:1].upper() + summary[1:]}.\n\n```text\n{text.rstrip()}\n```\n"
        target = folder / f"{name}.md"
        if not target.exists() or target.read_text(encoding="utf-8") != page:  # unchanged: no rebuild
            target.write_text(page, encoding="utf-8")
    return list(pages)


def _generate(app):
    write_pages(Path(app.srcdir) / "cli")


def setup(app):
    app.connect("builder-inited", _generate)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
