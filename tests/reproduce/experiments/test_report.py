"""Generated blocks of a report are replaced, and only they."""

import pytest

from novelty.reproduce.experiments import report

TEXT = ("# Report\n<!-- BEGIN generated: a -->\nold a\n<!-- END generated: a -->\nwords\n"
        "<!-- BEGIN generated: b-claims -->\nold b\n<!-- END generated: b-claims -->\n")


def test_fill_replaces_every_block_and_keeps_the_words():
    out = report.fill(TEXT, {"a": "new a\n", "b-claims": "| x |"})
    assert out == TEXT.replace("old a", "new a").replace("old b", "| x |")


def test_a_block_without_content_is_an_error_unless_partial():
    with pytest.raises(ValueError, match=r"\['b-claims'\]"):
        report.fill(TEXT, {"a": "new"})
    assert report.fill(TEXT, {"a": "new"}, partial=True) == TEXT.replace("old a", "new")
