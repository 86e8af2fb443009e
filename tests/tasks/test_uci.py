"""The real-data loaders, on the shared files and on small malformed files."""

from pathlib import Path

import numpy as np
import pytest

from novelty import datasets
from novelty.tasks.uci import WALL_FOLLOWING_CLASSES

#: The project's shared folder of public data, beside the repository.
SHARED = (Path(__file__).resolve().parents[2] / ".." / "shared" / "datasets").resolve()


@pytest.fixture(scope="module")
def shared_data() -> Path:
    if not SHARED.is_dir():
        pytest.skip(f"the shared data folder {SHARED} is absent (it lives beside the repository)")
    return SHARED

WF = "wall-following-robot-navigation"
SONAR = "sonar-mines-vs-rocks"


def _need(shared_data, folder, name):
    path = shared_data / folder / name
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    return path


def test_wall_following_shape_class_counts_and_encoding(shared_data):
    path = _need(shared_data, WF, "sensor_readings_24.data")
    ds = datasets.load("uci-wall-following", path=path)
    assert ds.X.shape == (5456, 24)
    assert ds.metadata["class_counts"] == {"Move-Forward": 2205, "Sharp-Right-Turn": 2097,
                                           "Slight-Right-Turn": 826, "Slight-Left-Turn": 328}
    assert 0.0 <= ds.X.min() and ds.X.max() <= 1.0
    raw = datasets.load("uci-wall-following", path=path, normalise=False)
    # the README's summary statistics for US1: max 5.0, min 0.4, mean 1.47162
    assert raw.X[:, 0].max() == pytest.approx(5.0)
    assert raw.X[:, 0].min() == pytest.approx(0.4)
    assert raw.X[:, 0].mean() == pytest.approx(1.47162, abs=1e-4)
    np.testing.assert_allclose(ds.X, 1 - np.minimum(raw.X, 5.0) / 5.0)


def test_wall_following_found_from_folder_and_environment_variable(shared_data, monkeypatch):
    _need(shared_data, WF, "sensor_readings_24.data")
    by_folder = datasets.load("uci-wall-following", path=shared_data / WF)
    monkeypatch.setenv("NOVELTY_DATA_DIR", str(shared_data))
    by_env = datasets.load("uci-wall-following")
    np.testing.assert_array_equal(by_folder.X, by_env.X)


def test_wall_following_task_split(shared_data):
    _need(shared_data, WF, "sensor_readings_24.data")
    task = datasets.load("uci-wall-following-novelty", path=shared_data)
    train, test = task.train(), task.test()
    assert set(train.columns["class"]) <= {"Move-Forward", "Slight-Right-Turn"}
    assert train.y.sum() == 0
    assert len(test) == 5456 - 2728
    novel = np.isin(task.columns["class"][task.split == "test"],
                    ["Sharp-Right-Turn", "Slight-Left-Turn"])
    np.testing.assert_array_equal(test.y, novel.astype(int))
    # time order is kept: training rows come from the first half of the file
    assert task.columns["row_index"][task.split == "train"].max() < 2728


def test_sonar_shape_counts_and_mines_task(shared_data):
    _need(shared_data, SONAR, "sonar.all-data")
    ds = datasets.load("uci-sonar", path=shared_data)
    assert ds.X.shape == (208, 60)
    assert ds.metadata["class_counts"] == {"R": 97, "M": 111}
    task = datasets.load("uci-sonar-mines", path=shared_data, seed=0)
    train, test = task.train(), task.test()
    assert len(train) == 48 and set(train.columns["class"]) == {"R"}
    assert test.y.sum() == 111 and len(test) == 49 + 111
    other = datasets.load("uci-sonar-mines", path=shared_data, seed=1)
    assert not np.array_equal(task.X, other.X)
    again = datasets.load("uci-sonar-mines", path=shared_data, seed=0)
    np.testing.assert_array_equal(task.X, again.X)


def test_no_path_and_no_environment_variable_says_what_to_do(monkeypatch):
    monkeypatch.delenv("NOVELTY_DATA_DIR", raising=False)
    with pytest.raises(FileNotFoundError, match="path="):
        datasets.load("uci-sonar")


def test_a_folder_without_the_file_names_where_it_looked(tmp_path):
    with pytest.raises(FileNotFoundError, match="sonar.all-data"):
        datasets.load("uci-sonar", path=tmp_path)


def _row(n, label, value="0.5"):
    return ",".join([value] * n + [label])


@pytest.mark.parametrize("line, message", [
    (_row(23, "Move-Forward"), "expected 24 numbers"),
    (_row(24, "Move-Forward", value="abc"), "'abc' is not a number"),
    (_row(24, "Reverse"), "unknown label 'Reverse'"),
    (_row(24, "Move-Forward", value="nan"), "finite"),
])
def test_malformed_wall_following_file_names_file_and_line(tmp_path, line, message):
    good = _row(24, "Move-Forward")
    path = tmp_path / "sensor_readings_24.data"
    path.write_text("\r\n".join([good, good, line, good]) + "\r\n")
    with pytest.raises(ValueError, match=message) as err:
        datasets.load("uci-wall-following", path=path)
    assert f"{path}, line 3" in str(err.value)


def test_malformed_sonar_values_out_of_range(tmp_path):
    path = tmp_path / "sonar.all-data"
    path.write_text(_row(60, "R") + "\n" + _row(60, "M", value="1.5") + "\n")
    with pytest.raises(ValueError, match=r"line 2: values must lie in \[0.0, 1.0\]"):
        datasets.load("uci-sonar", path=path)


def test_empty_file_is_refused(tmp_path):
    path = tmp_path / "sonar.all-data"
    path.write_text("\n\n")
    with pytest.raises(ValueError, match="no data rows"):
        datasets.load("uci-sonar", path=path)


def test_small_wellformed_file_loads_with_crlf(tmp_path):
    path = tmp_path / "w.data"
    rows = [_row(24, c, value="2.5") for c in WALL_FOLLOWING_CLASSES]
    path.write_text("\r\n".join(rows) + "\r\n")
    ds = datasets.load("uci-wall-following", path=path)
    assert ds.X.shape == (4, 24)
    assert ds.X == pytest.approx(np.full((4, 24), 0.5))


def test_task_parameters_are_validated(tmp_path):
    with pytest.raises(ValueError, match="train_fraction"):
        datasets.load("uci-sonar-mines", path=tmp_path, train_fraction=1.0)
    with pytest.raises(ValueError, match="normal"):
        datasets.load("uci-wall-following-novelty", path=tmp_path, normal=("Fly",))
