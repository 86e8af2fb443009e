import numpy as np
import pytest

from novelty import sonar


def test_simulate_concatenates_runs_and_labels_them():
    ds = sonar.simulate("control", runs=2, seed=1, first_run=5)
    assert ds.X.shape == (200, 16)
    assert ds.run.tolist() == [5] * 100 + [6] * 100
    assert ds.metadata["runs"] == [5, 6]
    np.testing.assert_array_equal(ds.X[100:], sonar.simulate_run("control", 1, 6).X)


@pytest.mark.parametrize("runs", [0, -1, 1.5, True])
def test_simulate_rejects_bad_run_counts(runs):
    with pytest.raises(ValueError, match="runs"):
        sonar.simulate("a", runs=runs)


def test_negative_seed_is_refused():
    with pytest.raises(ValueError, match="seed"):
        sonar.simulate_run("a", seed=-1)


def test_write_dataset_npz_and_csv(tmp_path):
    import csv
    import json

    ds = sonar.simulate("a", seed=0)
    npz = sonar.write_dataset(ds, tmp_path / "a.npz")
    with np.load(npz, allow_pickle=False) as f:
        np.testing.assert_array_equal(f["X"], ds.X)
        np.testing.assert_array_equal(f["distance"], ds.distance)
        np.testing.assert_array_equal(f["run"], ds.run)
        ids = json.loads(str(f["feature_ids"]))
        assert [set(i) for i in ids] == [set(map(str, f)) for f in ds.feature_ids]
        assert json.loads(str(f["metadata"]))["map"] == ds.metadata["map"]
    path = sonar.write_dataset(ds, tmp_path / "a.csv")
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], rows[1:]
    assert header[:2] == ["s0", "s1"] and header[16:] == ["distance", "run", "features"]
    assert len(body) == 100
    np.testing.assert_allclose(np.array([r[:16] for r in body], dtype=float), ds.X, atol=1e-9)
    np.testing.assert_allclose([float(r[16]) for r in body], ds.distance, atol=1e-9)
    assert [set(filter(None, r[18].split(";"))) for r in body] == [set(map(str, f)) for f in ds.feature_ids]
    with pytest.raises(ValueError, match=".npz or .csv"):
        sonar.write_dataset(ds, tmp_path / "a.txt")


def test_ring_log_exposes_raw_readings():
    log = sonar.simulate_rings("a", 0, 0)
    assert log.readings.shape[1] == 16
    assert log.readings.min() >= 0.15 and log.readings.max() <= 6.5
    # about two rings per 10 cm at the default speed and ring period
    assert 150 <= log.readings.shape[0] <= 260
    assert np.all(np.diff(log.travelled) > 0)
