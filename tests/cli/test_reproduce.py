"""``novelty reproduce``: Table 1 and the figures written, experiments and their report blocks, user errors."""

import functools
from pathlib import Path

import pytest

from novelty.cli import main
from novelty.reproduce import run_protocol, table1_markdown, table1_rows


@functools.lru_cache(maxsize=None)
def protocol(seed: int) -> dict:
    return {(t.experiment, t.trial): t for t in run_protocol(seed=seed)}


@pytest.mark.slow
def test_reproduce_command_writes_table_and_figures(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    expected = table1_markdown(table1_rows(list(protocol(0).values())))  # also caches the traversals
    assert main(["reproduce", "--seed", "0", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert expected in out and "| A | 1 (L) |" in out and "| 9.17 | 1.00 |" in out
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["figure4-experiment1.png", "figure5-experiments2-3.png", "table1.csv", "table1.md"]
    for name in names[:2]:
        data = (tmp_path / name).read_bytes()
        assert data[:4] == b"\x89PNG" and len(data) > 10_000
    assert expected in (tmp_path / "table1.md").read_text()
    assert not plt.get_fignums()  # every figure closed


def test_reproduce_experiment_writes_its_table_figure_and_report_block(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    report = tmp_path / "report.md"
    report.write_text("Intro\n<!-- BEGIN generated: maxima -->\nstale\n<!-- END generated: maxima -->\nEnd\n")
    argv = ["reproduce", "--experiment", "maxima", "--out", str(tmp_path / "out"), "--report", str(report)]
    assert main(argv) == 0
    assert "| 0.42 | A 4, A 5, B 2, B 3, C 4 |" in capsys.readouterr().out
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["maxima.csv", "maxima.md", "maxima.png"]
    text = report.read_text()
    assert text.startswith("Intro\n") and text.endswith("End\n") and "stale" not in text
    assert "| 0.42 | A 4, A 5, B 2, B 3, C 4 | none | none | 3 winner (0.4174) |" in text


@pytest.mark.parametrize("argv, message", [
    (["--detector", "no-such-detector"], "Unknown detector"),
    (["--param", "bogus=1"], "bogus"),
    (["--a-pairs", "0"], "--a-pairs"),
    (["--experiment", "no-such"], "known: table1, synthetic"),
    (["--report", "r.md"], "--experiment"),
])
def test_reproduce_command_user_errors_are_one_line(argv, message, tmp_path, capsys):
    assert main(["reproduce", "--no-figures", "--out", str(tmp_path), *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err and message in err


def test_the_guide_shows_the_table_the_command_prints():
    section = (Path(__file__).resolve().parents[2] / "docs" / "guide" / "paper.md").read_text(encoding="utf-8")
    assert "novelty reproduce" in section
    assert table1_markdown(table1_rows(list(protocol(0).values()))) in section


def test_a_report_the_experiments_would_write_over_is_refused_before_they_run(tmp_path, capsys):
    report = tmp_path / "maxima.md"
    report.write_text("<!-- BEGIN generated: maxima -->\n<!-- END generated: maxima -->\n")
    assert main(["reproduce", "--experiment", "maxima", "--out", str(tmp_path), "--report", str(report)]) == 2
    assert "is a file the experiments write in --out" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["maxima.md"]
