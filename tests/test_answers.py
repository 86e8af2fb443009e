"""The answers of "Which detector?" are named once (novelty.answers) and every place that points a robot's
user to a detector names one of them: the guide's generated answers, the command line's examples, the
guides' commands on recordings and live streams."""

import importlib.util
import re
import sys
from pathlib import Path

import pytest

from novelty.answers import ANSWERS, PAPER
from novelty.cli import run, score

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
#: a command that streams a robot's recording or a live topic through a detector
ROBOT_RUN = re.compile(r"novelty run (?P<detector>[\w-]+) --data (?P<data>\S+)")
RECORDING = re.compile(r"(\.log(\.gz)?|\.bag|\.db3|\.mcap|^-)$")


def robot_runs(text: str) -> list[tuple[str, str]]:
    return [(m["detector"], m["data"]) for m in ROBOT_RUN.finditer(text) if RECORDING.search(m["data"])]


def test_the_guides_answers_read_their_names_from_the_package(monkeypatch):
    spec = importlib.util.spec_from_file_location("which_detector", ROOT / "benchmarks" / "which_detector.py")
    which = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "which_detector", which)   # a dataclass's module must be importable
    spec.loader.exec_module(which)
    assert {a.key: a.use for a in which.ANSWERS} == ANSWERS


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_the_guides_stream_a_robots_recordings_through_an_answer(page):
    """hsom is the paper's detector, near chance on recordings: a guide streams a recording through the
    detector that answers the question of its command."""
    found = robot_runs(page.read_text(encoding="utf-8"))
    wrong = [f"novelty run {d} --data {data}" for d, data in found if d not in set(ANSWERS.values()) - {PAPER}]
    assert not wrong, f"{page.name}: recordings streamed through a detector that answers no question: {wrong}"


def test_the_command_lines_examples_on_recordings_name_answers():
    found = [pair for example in run.EXAMPLES + score.EXAMPLES for pair in robot_runs(example)]
    assert len(found) >= 5 and all(d in set(ANSWERS.values()) - {PAPER} for d, _ in found), found
