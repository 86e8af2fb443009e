"""``novelty list`` prints descriptions as text, without docstring markup."""

import re

from novelty.cli import main


def test_no_sphinx_roles_or_backquotes_in_the_listing(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    assert ":func:" not in out and ":class:" not in out and "`" not in out
    assert "(see inspection)" in out


def test_no_description_repeats_a_word_once_its_markup_is_gone(capsys):
    # "on each of ``runs`` runs" read "on each of runs runs" in a terminal
    assert main(["list"]) == 0
    repeated = [line.strip() for line in capsys.readouterr().out.splitlines()
                if re.search(r"\b(\w+) \1\b", line, flags=re.I)]
    assert not repeated, repeated
