"""The exploration protocol: policies, the suite's hooks, and every backend agreeing."""

import numpy as np
import pytest

import novelty
from novelty.bench import DetectorSpec, Suite, SuiteError, TaskSpec
from novelty.bench.cell import run_cell
from novelty.bench.exploration.prequential import EXPLORATION_COLUMNS, parse_policy, place_metrics, prequential
from novelty.bench.runner import run_bench
from novelty.bench import suite_from_dict
from novelty.bench.exploration.metrics import first_encounter_auc

RNG = np.random.default_rng(0)
X = RNG.random((40, 3))
RUN = np.repeat([0, 1, 2, 3], 10)


@pytest.fixture
def toy_exploration():
    import toy

    from novelty.datasets import registry as datasets

    datasets.register(toy.EXPLORATION, toy.toy_exploration, description="A tiny exploration (tests).",
                      replace=True)
    yield toy
    datasets.unregister(toy.EXPLORATION)


def make_parzen():
    return novelty.make("parzen")


def test_online_scores_each_scan_before_learning_it():
    out, det = prequential(lambda: novelty.make("hsom", random_state=0), X, RUN, 2, "online")
    np.testing.assert_array_equal(out, novelty.make("hsom", random_state=0).stream(X))


def test_frozen_online_detector_learns_the_warmup_only():
    out, det = prequential(lambda: novelty.make("hsom", random_state=0), X, RUN, 2, "frozen")
    ref = novelty.make("hsom", random_state=0)
    np.testing.assert_array_equal(out[:20], ref.stream(X[:20]))
    np.testing.assert_array_equal(out[20:], ref.novelty(X[20:]))


@pytest.mark.parametrize("policy, fitted_on", [
    ("frozen", {1: [0], 2: [0, 1], 3: [0, 1]}),
    ("refit", {1: [0], 2: [0, 1], 3: [0, 1, 2]}),
    ("window=2", {1: [0], 2: [0, 1], 3: [1, 2]}),
])
def test_refitting_policies_score_a_run_by_the_model_of_runs_before_it(policy, fitted_on):
    out, _ = prequential(make_parzen, X, RUN, 2, policy)
    np.testing.assert_array_equal(out[:10], 1.0)  # nothing is familiar before the first fit
    for r, seen in fitted_on.items():
        expected = make_parzen().fit(X[np.isin(RUN, seen)]).novelty(X[RUN == r])
        np.testing.assert_array_equal(out[RUN == r], expected)


@pytest.mark.parametrize("text", ["sometimes", "window", "window=0", "window=x", "frozen=2", 3])
def test_bad_policies_are_refused(text):
    with pytest.raises(SuiteError, match="policy"):
        parse_policy(text)


def test_the_suite_shows_each_policy_in_the_label():
    suite = suite_from_dict({
        "suite": {"protocol": "exploration"},
        "detectors": [{"name": "hsom"}, {"name": "parzen"}, {"name": "parzen", "policy": "window=3"},
                      {"name": "hsom", "policy": "frozen"}],
        "tasks": [{"name": "exploration-open-door"}]})
    assert [d.label for d in suite.detectors] == ["hsom", "parzen (frozen)", "parzen (window=3)",
                                                  "hsom (frozen)"]
    assert {c.protocol for c in suite.cells()} == {"exploration"}


@pytest.mark.parametrize("data, message", [
    ({"suite": {"protocol": "streaming"}}, "Unknown protocol"),
    ({"detectors": [{"name": "parzen", "policy": "refit"}]}, "policies are for"),
    ({"suite": {"protocol": "exploration"}, "detectors": [{"name": "parzen", "policy": "online"}]},
     "learns in batch only"),
])
def test_suite_refuses_what_it_cannot_run(data, message):
    data = {"detectors": [{"name": "hsom"}], "tasks": [{"name": "exploration-open-door"}], **data}
    with pytest.raises(SuiteError, match=message):
        suite_from_dict(data)


def test_holdout_cells_keep_their_ids():
    # the exploration hooks add keys only when used, so that earlier results still resume
    cell = Suite([DetectorSpec("hsom")], [TaskSpec("paper-a-to-a-star")]).check().cells()[0]
    assert cell.id == "d2c7b63757e380bf"  # its id before the exploration protocol existed
    assert "protocol" not in cell.key and "policy" not in cell.key["detector"]


def test_a_cell_of_the_exploration_protocol(toy_exploration):
    suite = Suite([DetectorSpec("hsom", {"n_rows": 3, "n_columns": 3})], [TaskSpec(toy_exploration.EXPLORATION)],
                  protocol="exploration").check()
    row, arrays = run_cell(suite.cells()[0])
    assert row["status"] == "ok", row["error"]
    assert set(EXPLORATION_COLUMNS) <= set(row)
    data = toy_exploration.toy_exploration()
    expected = novelty.make("hsom", n_rows=3, n_columns=3, random_state=0).stream(data.X)
    np.testing.assert_array_equal(arrays["novelty"], expected)
    assert row["policy"] == "online" and row["n_runs"] == 6 and row["n_first"] == 4
    columns = data.columns
    assert row["first_encounter_auc"] == first_encounter_auc(expected, data.run, columns["feature"],
                                                             columns["exposure"], 1)
    assert row["first_encounter_auc"] > 0.5  # the door is far from everything familiar


def test_a_plain_task_is_refused_by_the_exploration_protocol(toy_registered):
    suite = Suite([DetectorSpec("hsom")], [TaskSpec(toy_registered.TASK)], protocol="exploration").check()
    row, _ = run_cell(suite.cells()[0])
    assert row["status"] == "error" and "is not an exploration task" in row["error"]


def metric_table(rows):
    return {(r["detector"], r["seed"]): {c: r.get(c) for c in ["status", *EXPLORATION_COLUMNS]}
            for r in rows}


@pytest.mark.slow
def test_serial_joblib_and_dask_give_the_same_numbers(tmp_path, toy_exploration):
    distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed")
    suite = Suite([DetectorSpec("gwr-novelty"), DetectorSpec("parzen", label="parzen (refit)", policy="refit")],
                  [TaskSpec(toy_exploration.EXPLORATION)], seeds=[0, 1], protocol="exploration").check()
    serial = run_bench(suite, tmp_path / "serial", quiet=True, plots=False)
    assert all(r["status"] == "ok" for r in serial.rows)
    parallel = run_bench(suite, tmp_path / "joblib", backend="joblib", jobs=2, quiet=True, plots=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        dask = run_bench(suite, tmp_path / "dask", backend="dask", scheduler=cluster.scheduler_address,
                         quiet=True, plots=False)
    assert metric_table(parallel.rows) == metric_table(serial.rows) == metric_table(dask.rows)


def test_an_exploration_run_writes_its_table_and_plots(tmp_path, toy_exploration):
    suite = Suite([DetectorSpec("hsom", {"n_rows": 3, "n_columns": 3}, "hsom-3x3")],
                  [TaskSpec(toy_exploration.EXPLORATION)], protocol="exploration").check()
    report = run_bench(suite, tmp_path, quiet=True)
    assert "## Exploration: first encounters and habituation" in (tmp_path / "summary.md").read_text()
    assert "| hsom-3x3 " in report.table
    pytest.importorskip("matplotlib", reason="matplotlib is not installed")
    assert {p.name for p in (tmp_path / "plots").iterdir()} == {
        f"exploration-{kind}-{toy_exploration.EXPLORATION}.png" for kind in ("route", "exposure", "learning")}


def test_a_run_compares_on_an_exploration_task_over_its_worlds(tmp_path, toy_exploration):
    suite = Suite([DetectorSpec("hsom", {"n_rows": 3, "n_columns": 3}), DetectorSpec("kmeans-stanley")],
                  [TaskSpec(toy_exploration.EXPLORATION)], seeds=[0, 1, 2], protocol="exploration",
                  reference="kmeans-stanley").check()
    report = run_bench(suite, tmp_path, quiet=True, plots=False, compare_on=[toy_exploration.EXPLORATION])
    rows = {r["seed"]: r for r in report.rows if r["detector"] == "hsom"}
    ref = {r["seed"]: r for r in report.rows if r["detector"] == "kmeans-stanley"}
    d = [rows[s]["first_encounter_auc"] - ref[s]["first_encounter_auc"] for s in range(3)]
    assert len({r["task_data"] for r in rows.values()}) == 3                   # each seed builds its world
    section = "\n".join(report.comparisons)
    assert "Unit: the seed, each an independently built world." in section and f"{np.mean(d):+.3f}" in section


def test_first_sights_in_seen_and_unseen_places_are_scored_apart_against_their_runs_familiar_scans():
    # run 0 is the warm-up; run 1: "a" seen first (0.9) and "b" unseen first (0.2) beside a familiar 0.3;
    # run 2: "a" again (its second exposure) beside a familiar 0.4
    novelty = [0.7, 0.9, 0.3, 0.2, 0.4, 0.5]
    run = [0, 1, 1, 1, 2, 2]
    feature = ["", "a", "", "b", "", "a"]
    exposure = [-1, 0, -1, 0, -1, 1]
    seen_place = [False, True, False, False, False, True]
    assert place_metrics(novelty, run, feature, exposure, 1, seen_place) == {
        "n_first_seen": 1, "first_encounter_auc_seen": 1.0, "n_first_unseen": 1, "first_encounter_auc_unseen": 0.0}
