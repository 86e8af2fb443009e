"""``novelty score``: a saved model scores files and recordings (CARMEN logs, ROS bags) frozen, and
calibrates its threshold on a familiar stretch for a stated false-alarm rate; its outputs never
replace the model or the scans it reads."""

import csv
import io

import numpy as np
import pytest

import novelty
from novelty.cli import main
from novelty.conformal import conformal_p_values, conformal_threshold
from novelty.io import Reading, read_rings
from novelty.sonar import preprocess


def table(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO(text)))


def write_log(path, n=60, seed=0):
    """A CARMEN log of ``n`` FLASER scans of 4 beams, one a second, the robot 0.1 m further each."""
    rng = np.random.default_rng(seed)
    with open(path, "w") as fh:
        for i in range(n):
            ranges = " ".join(f"{r:.3f}" for r in rng.uniform(0.5, 5.0, 4))
            fh.write(f"FLASER 4 {ranges} {0.1 * i} 0 0 {0.1 * i} 0 0 {100.0 + i} robot {100.0 + i}\n")
    return path


def rings(path):
    return preprocess(np.array([r.ranges for r in read_rings(path, Reading(sectors=2))]))


@pytest.fixture
def model(tmp_path):
    """An hsom learned on a log of its own (read as novelty run reads it: 2 sectors)."""
    learned = write_log(tmp_path / "learned.log", seed=1)
    det = novelty.make("hsom", n_rows=3, n_columns=3).fit(rings(learned))
    det.save(tmp_path / "hsom.npz")
    return tmp_path / "hsom.npz"


def test_a_carmen_log_is_scored_frozen_with_its_poses(model, tmp_path, capsys):
    log = write_log(tmp_path / "new.log")
    assert main(["score", "--model", str(model), "--data", str(log), "--sectors", "2"]) == 0
    rows = table(capsys.readouterr().out)
    assert list(rows[0]) == ["scan", "novelty", "alarm", "threshold", "time", "x", "y", "theta"]
    expected = novelty.load(model).novelty(rings(log))
    assert [float(r["novelty"]) for r in rows] == pytest.approx(expected, abs=1e-9)
    assert [int(r["alarm"]) for r in rows] == (expected > 0.5).astype(int).tolist()
    assert rows[3]["x"] == "0.3" and rows[3]["time"] == "103.0"


def test_a_gzipped_log_is_read_as_run_reads_it(model, tmp_path, capsys):
    import gzip

    log = write_log(tmp_path / "new.log")
    packed = tmp_path / "new.log.gz"
    packed.write_bytes(gzip.compress(log.read_bytes()))
    assert main(["score", "--model", str(model), "--data", str(packed), "--sectors", "2"]) == 0
    assert len(table(capsys.readouterr().out)) == 60


def test_a_time_range_calibrates_the_threshold_for_the_rate(model, tmp_path, capsys):
    log = write_log(tmp_path / "new.log")
    out, saved = tmp_path / "scored.csv", tmp_path / "calibrated.npz"
    assert main(["score", "--model", str(model), "--data", str(log), "--sectors", "2", "--calibrate", "10:40",
                 "--false-alarm-rate", "0.1", "--out", str(out), "--save", str(saved)]) == 0
    err = capsys.readouterr().err
    novelty_all = novelty.load(model).novelty(rings(log))
    familiar = novelty_all[10:40]                         # 10 s to 40 s after the first scan: scans 10-39
    threshold = conformal_threshold(familiar, 0.1)         # the 28th smallest of 30: ceil(31 * 0.9) = 28
    assert threshold == np.sort(familiar)[27]
    rows = table(out.read_text())
    assert [int(r["alarm"]) for r in rows] == (novelty_all > threshold).astype(int).tolist()
    assert [float(r["p_value"]) for r in rows] == pytest.approx(conformal_p_values(novelty_all, familiar))
    assert f"threshold {threshold:.6g}, for a false-alarm rate of 0.1" in err and "(30 scans, scored frozen)" in err
    back = novelty.load(saved)
    assert back.threshold_ == threshold and back.calibrated_on_.endswith("10 s to 40 s after its first scan "
                                                                         "(30 scans, scored frozen)")


def test_rows_of_a_file_and_a_file_of_its_own_calibrate_too(tmp_path, capsys):
    X = np.random.default_rng(0).uniform(size=(80, 3))
    np.savez(tmp_path / "scans.npz", X=X)
    np.savez(tmp_path / "familiar.npz", X=X[:25] + 0.01)
    det = novelty.make("parzen").fit(np.random.default_rng(1).uniform(size=(50, 3)))
    det.save(tmp_path / "p.npz")
    for stretch, familiar in [("rows:20:45", X[20:45]), (str(tmp_path / "familiar.npz"), X[:25] + 0.01)]:
        assert main(["score", "--model", str(tmp_path / "p.npz"), "--data", str(tmp_path / "scans.npz"),
                     "--calibrate", stretch, "--false-alarm-rate", "0.2"]) == 0
        rows = table(capsys.readouterr().out)
        threshold = conformal_threshold(det.novelty(familiar), 0.2)
        assert [int(r["alarm"]) for r in rows] == (det.novelty(X) > threshold).astype(int).tolist()


@pytest.mark.parametrize("options, message", [
    (["--false-alarm-rate", "0.1"], "--false-alarm-rate needs --calibrate"),
    (["--calibrate", "0:10", "--false-alarm-rate", "1.5"], "--false-alarm-rate must be a number in (0, 1)"),
    (["--calibrate", "rows:5:2"], "expected 0 <= I < J"),
    (["--calibrate", "500:600"], "no scan of"),
    (["--save", "m2.npz"], "--save writes the calibrated model: give --calibrate too"),
    (["--calibrate", "rows:0:5", "--columns", "0"], "no --passes, --bin-length, --columns or --preprocess"),
])
def test_what_score_cannot_do_is_said_in_its_options(model, tmp_path, capsys, options, message):
    log = write_log(tmp_path / "new.log")
    assert main(["score", "--model", str(model), "--data", str(log), "--sectors", "2", *options]) == 2
    assert message in capsys.readouterr().err


def test_an_uncalibrated_threshold_that_does_not_carry_over_says_how_to_calibrate(tmp_path, capsys):
    X = np.random.default_rng(0).uniform(size=(300, 4))
    novelty.make("kmeans-stanley").fit(X[:200]).save(tmp_path / "km.npz")
    np.savez(tmp_path / "new.npz", X=X[200:])
    assert main(["score", "--model", str(tmp_path / "km.npz"), "--data", str(tmp_path / "new.npz")]) == 0
    err = capsys.readouterr().err
    assert "novelty score: threshold=0.5 meets a novelty whose mismatch term" in err
    assert "Give --calibrate with a stretch the robot knows (and --false-alarm-rate)" in err
    assert "det.calibrate" not in err


@pytest.fixture(scope="module", params=("ros1", "mcap"))
def bag(request, tmp_path_factory):
    pytest.importorskip("rosbags", reason="reading ROS bags needs the optional extra: pip install "
                        "'novelty-habituation[ros]'")
    from ..io.bag_files import write_bag

    return write_bag(tmp_path_factory.mktemp(request.param), request.param)


def test_a_bag_is_scored_with_the_options_run_reads_it_with(bag, tmp_path, capsys):
    det = novelty.make("hsom", n_rows=2, n_columns=2).fit(np.random.default_rng(0).uniform(size=(20, 2)))
    det.save(tmp_path / "m.npz")
    assert main(["score", "--model", str(tmp_path / "m.npz"), "--data", str(bag), "--topic", "/scan",
                 "--sectors", "2", "--pose-topic", "/odom"]) == 0
    rows = table(capsys.readouterr().out)
    expected = det.novelty(preprocess(np.array([r.ranges for r in read_rings(bag, Reading(topic="/scan", sectors=2))])))
    assert [float(r["novelty"]) for r in rows] == pytest.approx(expected, abs=1e-9)
    assert [r["x"] for r in rows] == ["1", "1.1", "1.2", "5.95", "5.95"]
    assert main(["score", "--model", str(tmp_path / "m.npz"), "--data", str(bag), "--topic", "/nothing"]) == 2
    assert "/scan" in capsys.readouterr().err   # the bag's topics are listed


def test_an_output_naming_the_model_or_the_data_is_refused_before_anything_is_read(tmp_path, capsys):
    data = tmp_path / "scans.csv"
    data.write_text("a,b\n0.1,0.2\n0.3,0.4\n")
    model = tmp_path / "m.npz"
    assert main(["run", "hsom", "--data", str(data), "--param", "n_rows=2", "--save", str(model)]) == 0
    saved = model.read_bytes()
    capsys.readouterr()
    for option, target in (("--model", model), ("--data", data)):
        assert main(["score", "--model", str(model), "--data", str(data), "--out", str(target)]) == 2
        captured = capsys.readouterr()
        assert f"--out {target} is the file {option} names" in captured.err and captured.out == ""
    for _, target in (("--model", model), ("--data", data), ("--calibrate", data)):
        assert main(["score", "--model", str(model), "--data", str(data), "--calibrate", str(data),
                     "--save", str(target)]) == 2
        assert f"--save {target} is the file" in capsys.readouterr().err
    assert model.read_bytes() == saved and data.read_text() == "a,b\n0.1,0.2\n0.3,0.4\n"
    assert np.load(model, allow_pickle=False).files   # still a model file
