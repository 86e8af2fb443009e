"""Every study's suite loads as ``novelty bench`` reads it, and the command written at its top runs it from
where it lies (the suites moved with their studies; a command left naming the old place would fail)."""

import re
from pathlib import Path

import pytest

from novelty.bench import load_suite

STUDIES = Path(__file__).resolve().parent
ROOT = STUDIES.parent
SUITES = sorted(STUDIES.rglob("*.toml"))
COMMAND = re.compile(r"novelty bench (\S+\.toml)")


def test_the_studies_hold_suites():
    assert len(SUITES) >= 10


@pytest.mark.parametrize("path", SUITES, ids=lambda p: p.relative_to(STUDIES).as_posix())
def test_a_study_suite_loads_and_its_command_names_it(path):
    suite = load_suite(path)
    assert suite.detectors and suite.tasks and suite.seeds
    named = COMMAND.findall(path.read_text(encoding="utf-8"))
    assert named == [path.relative_to(ROOT).as_posix()], f"the command at the top of {path.name} runs {named}"
