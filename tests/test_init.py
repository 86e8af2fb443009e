"""``import novelty``: cheap, with the subpackages reachable on first use."""

import subprocess
import sys
from pathlib import Path

import pytest

import novelty

ROOT = str(Path(novelty.__file__).parents[1])


def test_subpackages_are_reachable_after_import_novelty_alone_and_not_imported_before():
    code = ("import sys, novelty; before = 'novelty.datasets' in sys.modules; "
            "print(before, novelty.datasets.load.__module__, 'novelty.datasets' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={"PYTHONPATH": ROOT, "PATH": ""}, check=True).stdout.split()
    assert out == ["False", "novelty.datasets", "True"]


def test_the_conformance_suite_is_reachable_after_import_novelty_alone():
    code = "import novelty; print(novelty.testing.check_conformance.__module__)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={"PYTHONPATH": ROOT, "PATH": ""}, check=True).stdout.split()
    assert out == ["novelty.testing.conformance"]


def test_an_unknown_attribute_is_an_attribute_error():
    with pytest.raises(AttributeError, match="module 'novelty' has no attribute 'dataset'"):
        _ = novelty.dataset


HEAVY = ("numpy", "scipy", "sklearn", "numba", "matplotlib", "dask", "pyod", "river")


@pytest.mark.parametrize("code, allowed", [
    ("import novelty", ()),
    ("import novelty.cli; novelty.cli.build_parser()", ("numpy",)),  # the command line's start
])
def test_imports_stay_light(code, allowed):
    probe = f"{code}; import sys; print(' '.join(sorted({{m.split('.')[0] for m in sys.modules}})))"
    loaded = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120,
                            env={"PYTHONPATH": ROOT, "PATH": ""}, check=True).stdout.split()
    assert "novelty" in loaded
    assert [m for m in HEAVY if m in loaded and m not in allowed] == []
