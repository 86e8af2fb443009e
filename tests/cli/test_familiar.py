"""The familiar stretch of the command line (--calibrate, --false-alarm-rate), and novelty run calibrating
a learning detector on a stretch of its own stream."""

import csv
import io
import math

import numpy as np
import pytest

import novelty
from novelty.cli import main
from novelty.cli._common import UserError
from novelty.cli.familiar import Stretch, parse_stretch
from novelty.conformal import conformal_threshold

from .test_score import rings, write_log


def table(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO(text)))


@pytest.mark.parametrize("text, expected", [
    ("0:900", Stretch("0:900", seconds=(0.0, 900.0))),
    ("12.5:", Stretch("12.5:", seconds=(12.5, math.inf))),
    ("rows:100:200", Stretch("rows:100:200", rows=(100, 200.0))),
    ("rows:5:", Stretch("rows:5:", rows=(5, math.inf))),
    ("lap2.bag", Stretch("lap2.bag", path="lap2.bag")),
    ("C:/logs/lap2.log", Stretch("C:/logs/lap2.log", path="C:/logs/lap2.log")),
])
def test_the_three_forms_of_a_stretch(text, expected):
    assert parse_stretch(text) == expected


@pytest.mark.parametrize("text", ["rows:a:b", "rows:4:4", "rows:-1:3", "900:100", "-5:10"])
def test_a_malformed_stretch_is_refused(text):
    with pytest.raises(UserError, match="--calibrate"):
        parse_stretch(text)


def test_which_scans_a_stretch_holds():
    seconds, rows = parse_stretch("10:20"), parse_stretch("rows:2:4")
    assert [seconds.holds(i, t) for i, t in enumerate([0.0, 10.0, 19.9, 20.0])] == [False, True, True, False]
    assert [rows.holds(i, None) for i in range(5)] == [False, False, True, True, False]
    assert seconds.passed(9, 20.0) and not seconds.passed(9, 19.0) and rows.passed(4, None)
    with pytest.raises(UserError, match="no time column: name its rows instead"):
        seconds.holds(0, None)


def test_run_calibrates_on_its_own_stream_and_alarms_after_the_stretch(tmp_path, capsys):
    log = write_log(tmp_path / "drive.log")
    out, saved = tmp_path / "novelty.csv", tmp_path / "m.npz"
    params = ["--param", "n_rows=3", "--param", "n_columns=3"]
    assert main(["run", "hsom", "--data", str(log), "--sectors", "2", *params, "--calibrate", "20:40",
                 "--false-alarm-rate", "0.1", "--out", str(out), "--save", str(saved)]) == 0
    assert "(20 scans, scored as learned)" in capsys.readouterr().err
    streamed = novelty.make("hsom", n_rows=3, n_columns=3).stream(rings(log))
    threshold = conformal_threshold(streamed[20:40], 0.1)
    rows = table(out.read_text())
    # scans 20-39 calibrate: the threshold is known from scan 40 on, which comes 40 s after the first
    assert all(r["alarm"] == "" and r["p_value"] == "" for r in rows[:40])
    assert [int(r["alarm"]) for r in rows[40:]] == (streamed[40:] > threshold).astype(int).tolist()
    assert novelty.load(saved).threshold_ == threshold


def test_run_calibrates_a_file_by_rows_and_a_policy_uses_the_calibrated_threshold(tmp_path, capsys):
    X = np.random.default_rng(0).uniform(size=(60, 3))
    np.savez(tmp_path / "scans.npz", X=X)
    assert main(["run", "hsom", "--data", str(tmp_path / "scans.npz"), "--param", "n_rows=3", "--calibrate",
                 "rows:10:30", "--false-alarm-rate", "0.25", "--alarm", "k-of-n:2,3"]) == 0
    rows = table(capsys.readouterr().out)
    streamed = novelty.make("hsom", n_rows=3).stream(X)
    above = streamed > conformal_threshold(streamed[10:30], 0.25)
    expected = [int(above[max(30, i - 2):i + 1].sum() >= 2) for i in range(30, 60)]
    assert [r["alarm"] for r in rows[:30]] == [""] * 30 and [int(r["alarm"]) for r in rows[30:]] == expected


@pytest.mark.parametrize("detector, options, message", [
    ("hsom", ["--calibrate", "lap2.log"], "novelty run calibrates on a stretch of --data"),
    ("isolation-forest", ["--calibrate", "rows:0:10"], "learns in batch only: fitted on every scan"),
    ("hsom", ["--calibrate", "rows:100:200"], "no scan of --data lies in it"),
])
def test_what_run_cannot_calibrate_on_is_said(tmp_path, capsys, detector, options, message):
    np.savez(tmp_path / "scans.npz", X=np.random.default_rng(0).uniform(size=(30, 3)))
    assert main(["run", detector, "--data", str(tmp_path / "scans.npz"), *options]) == 2
    assert message in capsys.readouterr().err
