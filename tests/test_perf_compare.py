"""benchmarks/perf_compare.py: two revisions timed alternately, their medians and ratios."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("perf_compare", ROOT / "benchmarks" / "perf_compare.py")
perf_compare = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(perf_compare)


def test_the_table_gives_medians_over_rounds_and_each_rounds_ratio():
    before = [{"a": 3e-6}, {"a": 5e-6}, {"a": 4e-6}]
    after = [{"a": 2e-6}, {"a": 4e-6}, {"a": 1e-6}]
    lines = perf_compare.table(before, after).splitlines()
    # medians 4 us and 2 us: before / after 2.000; rounds 3/2, 5/4, 4/1
    assert lines[2] == "| a | 4.0 | 2.0 | 2.000 | 1.50 1.25 4.00 |"


def test_a_tree_that_fails_stops_the_comparison_with_its_error(tmp_path):
    import pytest

    with pytest.raises(SystemExit, match="timing .* failed"):
        perf_compare.measure(str(tmp_path), str(tmp_path / "cache"), None)  # no package there
