"""Table 1 beside the paper's: rows, CSV and markdown."""

import csv
import functools

import numpy as np

from novelty.reproduce import TABLE1_COLUMNS, run_protocol, table1_markdown, table1_rows, write_table1_csv


@functools.lru_cache(maxsize=None)
def protocol(seed: int) -> dict:
    return {(t.experiment, t.trial): t for t in run_protocol(seed=seed)}


def test_table1_rows_csv_and_markdown(tmp_path):
    rows = table1_rows(list(protocol(0).values()))
    assert rows[0]["paper_integrated"] == 9.17 and rows[16]["trial"] == "Control"
    write_table1_csv(rows, tmp_path / "table1.csv")
    with open(tmp_path / "table1.csv", newline="") as fh:
        read = list(csv.DictReader(fh))
    assert tuple(read[0]) == TABLE1_COLUMNS and len(read) == 23
    assert read[0]["mode"] == "L" and float(read[0]["integrated"]) == rows[0]["integrated"]
    md = table1_markdown(rows)
    assert md.count("\n") == 24 and "| A* | 1 (NL) |" in md and "| C | Control |" in md


def test_rows_beyond_the_papers_have_no_paper_values():
    trials = run_protocol(seed=0, a_pairs=4, experiments=("A",))
    rows = table1_rows(trials)
    assert [r["trial"] for r in rows] == [str(k) for k in range(1, 9)]
    assert np.isnan(rows[-1]["paper_integrated"]) and "| A | 8 (NL) | " in table1_markdown(rows)
    assert "—" in table1_markdown(rows).splitlines()[-1]
