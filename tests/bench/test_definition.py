"""A resumed run recomputes the cells whose detector or task resolves to something else now."""

import functools
import io
import json

import numpy as np
import pytest

import novelty
from novelty.bench import DetectorSpec, Suite, TaskSpec
from novelty.bench.definition import _without_location, definition_digest, describe
from novelty.bench.cell import run_cell
from novelty.bench.runner import run_bench
from novelty.bench.specs import Cell
from novelty.data import Dataset

PRESET = "bench-toy-preset"


def preset_of(n_rows):
    def preset(**params):
        """A preset whose definition changes between 'releases' (tests)."""
        return novelty.make("hsom", **{"n_rows": n_rows, "n_columns": 2, **params})
    return preset


@pytest.fixture
def preset():
    novelty.register_detector(PRESET, preset_of(2), replace=True)
    yield
    novelty.registry.detectors.unregister(PRESET)


def toy_suite(toy_registered, **task_options):
    return Suite([DetectorSpec(PRESET), DetectorSpec("hsom", {"n_rows": 2, "n_columns": 2}, "hsom-2x2")],
                 [TaskSpec(toy_registered.TASK, task_options)], seeds=[0, 1], name="toy").check()


def aucs(rows):
    return {(r["detector"], r["seed"]): r["roc_auc"] for r in rows}


def test_a_resume_recomputes_the_cells_of_a_preset_whose_definition_changed(tmp_path, toy_registered, preset):
    first = run_bench(toy_suite(toy_registered), tmp_path / "a", quiet=True, plots=False)
    assert first.ran == 4
    novelty.register_detector(PRESET, preset_of(5), replace=True)  # the preset's next release
    said = io.StringIO()
    resumed = run_bench(toy_suite(toy_registered), tmp_path / "a", progress=said, plots=False)
    assert (resumed.ran, resumed.skipped, resumed.stale) == (2, 2, 2)
    assert "2 of the 4 finished cells were computed by another definition" in said.getvalue()
    fresh = run_bench(toy_suite(toy_registered), tmp_path / "b", quiet=True, plots=False)
    assert aucs(resumed.rows) == aucs(fresh.rows)
    assert {r["n_units"] for r in resumed.rows if r["detector"] == PRESET} == {10}  # 5 x 2, not 2 x 2
    assert aucs(resumed.rows) != aucs(first.rows)


def test_rows_that_record_no_definition_are_recomputed_on_resume(tmp_path, toy_registered, preset):
    first = run_bench(toy_suite(toy_registered), tmp_path, quiet=True, plots=False)
    rows = [json.loads(line) for line in (tmp_path / "results.jsonl").read_text().splitlines()]
    assert all(len(row["definition"]) == 16 for row in rows)
    (tmp_path / "results.jsonl").write_text("".join(json.dumps({k: v for k, v in row.items() if k != "definition"})
                                                    + "\n" for row in rows))  # rows of an earlier release
    resumed = run_bench(toy_suite(toy_registered), tmp_path, quiet=True, plots=False)
    assert (resumed.ran, resumed.skipped, resumed.stale) == (4, 0, 4)
    assert aucs(resumed.rows) == aucs(first.rows)
    assert any("4 of the 4 finished cells" in note for note in resumed.notes)
    again = run_bench(toy_suite(toy_registered), tmp_path, quiet=True, plots=False)
    assert (again.ran, again.skipped, again.stale) == (0, 4, 0)


def test_a_resume_recomputes_the_cells_of_a_task_whose_data_changed(tmp_path, toy_registered, preset):
    from novelty.datasets import registry as datasets

    run_bench(toy_suite(toy_registered), tmp_path, quiet=True, plots=False)
    datasets.register(toy_registered.TASK, functools.partial(toy_registered.toy_task, novel_at=3), replace=True)
    resumed = run_bench(toy_suite(toy_registered), tmp_path, quiet=True, plots=False)
    assert (resumed.ran, resumed.stale) == (4, 4)


def test_a_run_in_worker_processes_records_the_definitions_the_parent_computes(tmp_path, toy_registered, preset):
    run_bench(toy_suite(toy_registered), tmp_path, backend="joblib", jobs=2, quiet=True, plots=False)
    resumed = run_bench(toy_suite(toy_registered), tmp_path, quiet=True, plots=False)
    assert (resumed.ran, resumed.skipped, resumed.stale) == (0, 4, 0)


# ----------------------------------------------------------------- describe
def cell(toy, detector="hsom", **params):
    return Cell(DetectorSpec(detector, params), TaskSpec(toy.TASK), 0)


def test_the_digest_follows_every_parameter_of_the_built_detector(toy_registered):
    base = definition_digest(cell(toy_registered))
    assert definition_digest(cell(toy_registered)) == base
    assert definition_digest(cell(toy_registered, alpha=1.05)) == base        # the default, written out
    assert definition_digest(cell(toy_registered, alpha=1.2)) != base         # a nested component's parameter
    assert definition_digest(cell(toy_registered, random_state=7)) != base    # the seed the suite sets
    assert definition_digest(Cell(DetectorSpec("hsom"), TaskSpec(toy_registered.TASK), 1)) != base
    assert definition_digest(Cell(DetectorSpec("hsom"), TaskSpec(toy_registered.TASK, {"n_test": 31}), 0)) != base


def test_where_the_data_was_read_from_is_not_part_of_the_task():
    data = Dataset("t", np.zeros((2, 1)), metadata={"source": "/a/x.csv", "seed": 0})
    moved = Dataset("t", np.zeros((2, 1)), metadata={"source": "/elsewhere/x.csv", "seed": 0})
    other = Dataset("t", np.zeros((2, 1)), metadata={"source": "/a/x.csv", "seed": 1})
    assert describe(_without_location(data)) == describe(_without_location(moved)) != describe(_without_location(other))


def plain(x):
    return x


class Holder:
    def __init__(self, value):
        self.value = value

    def __call__(self, x):
        return x * self.value


@pytest.mark.parametrize("a, b", [
    (1.0, 1),                                              # a float is not an int
    (np.zeros(2), np.zeros(2, dtype=np.float32)),          # nor float64 float32
    (np.zeros(2), np.zeros((2, 1))),                       # nor a shape another
    (np.array([0.0, 1.0]), np.array([0.0, 1.5])),
    (lambda x: x + 1, lambda x: x + 2),                    # two lambdas, one name
    (functools.partial(plain, 1), functools.partial(plain, 2)),
    (np.random.default_rng(0), np.random.default_rng(1)),
    (Holder(1), Holder(2)),                                # callable objects, by their state
    (Holder(1).__call__, Holder(2).__call__),              # bound methods, by their object
    (np.random.default_rng(0).random, np.random.default_rng(1).random),
    (np.exp, np.log),
    ({"a": 1}, {"a": 2}),
    (frozenset({"a"}), frozenset({"b"})),
    (float("nan"), float("inf")),
])
def test_describe_tells_apart_what_differs(a, b):
    assert json.dumps(describe(a)) != json.dumps(describe(b))  # the text the digest hashes


@pytest.mark.parametrize("make", [
    lambda: np.arange(3.0), lambda: np.random.default_rng(3), lambda: Holder([1, "a"]), lambda: plain,
    lambda: {"b": 1, "a": (2, 3)}, lambda: frozenset({"x", "y"}), lambda: object(), lambda: np.float64(0.25),
    lambda: novelty.make("explore"), lambda: novelty.SOM, lambda: np.array(["a", None], dtype=object),
])
def test_describe_is_the_same_for_equal_values_built_twice(make):
    described = describe(make())
    assert described == describe(make())
    json.dumps(described, allow_nan=False)  # plain JSON


def test_describe_reads_a_component_by_its_class_and_parameters():
    assert describe(novelty.StanleySynapse(alpha=2.0))["class"] == "novelty.habituation.stanley.StanleySynapse"
    assert describe(np.float64(0.25)) == 0.25 and describe(float("nan")) == "nan"
    assert describe(plain)["function"] == f"{__name__}.plain"
    assert describe(object()) == {"class": "builtins.object", "repr": "<object object>"}
    assert describe(Holder(3)) == {"class": f"{__name__}.Holder", "attributes": {"mapping": [["value", 3]]}}
    assert describe(np.exp) == {"callable": "numpy.exp"}


def test_seeds_of_one_world_share_their_task_data_and_seeds_of_built_worlds_do_not(toy_registered):
    built = [run_cell(Cell(DetectorSpec("hsom"), TaskSpec(toy_registered.TASK), s))[0] for s in (0, 1)]
    assert built[0]["task_data"] != built[1]["task_data"]            # the toy task's seed builds its data
    one = Dataset("one", np.random.default_rng(0).random((50, 4)), y=np.r_[np.zeros(45), np.ones(5)],
                  split=np.r_[np.full(30, "train"), np.full(20, "test")])
    recorded = [run_cell(Cell(DetectorSpec("hsom"), TaskSpec("one", data=one), s))[0] for s in (0, 1)]
    assert recorded[0]["task_data"] == recorded[1]["task_data"]      # one recording, two detector seeds
    assert recorded[0]["definition"] != recorded[1]["definition"]    # the seeds differ in the detector
