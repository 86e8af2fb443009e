"""``novelty list`` prints descriptions as text, without docstring markup."""

from novelty.cli import main


def test_no_sphinx_roles_or_backquotes_in_the_listing(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    assert ":func:" not in out and ":class:" not in out and "`" not in out
    assert "(see inspection)" in out
