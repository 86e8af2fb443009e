"""Suites from TOML and the command line; bad suites get one clear message."""

import io
from pathlib import Path

import pytest

from novelty.bench import Suite, SuiteError, load_suite, quick_suite_path, river
from novelty.bench.runner import run_bench


def write(tmp_path, text, name="suite.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_suite_with_a_grid_expands_into_cells(tmp_path, toy_registered):
    path = write(tmp_path, f"""
[suite]
name = "grid"
seeds = [0, 1, 2]

[[detectors]]
name = "hsom"
label = "small"
params = {{ n_rows = 3, n_columns = 3 }}
grid = {{ alpha = [1.05, 1.2], tau_winner = [3.33, 5.0] }}

[[tasks]]
name = "{toy_registered.TASK}"
options = {{ n_test = 20 }}
""")
    suite = load_suite(path)
    assert suite.name == "grid" and suite.seeds == [0, 1, 2]
    assert [d.label for d in suite.detectors] == [
        "small[alpha=1.05,tau_winner=3.33]", "small[alpha=1.05,tau_winner=5.0]",
        "small[alpha=1.2,tau_winner=3.33]", "small[alpha=1.2,tau_winner=5.0]"]
    assert suite.detectors[3].params == {"n_rows": 3, "n_columns": 3, "alpha": 1.2, "tau_winner": 5.0}
    cells = suite.cells()
    assert len(cells) == 4 * 1 * 3
    assert len({c.id for c in cells}) == 12
    assert cells[0].task.options == {"n_test": 20}


def test_seeds_as_a_count(tmp_path, toy_registered):
    path = write(tmp_path, f'[suite]\nseeds = 3\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "{toy_registered.TASK}"\n')
    assert load_suite(path).seeds == [0, 1, 2]


def test_optional_entries_are_skipped_when_not_registered(tmp_path, toy_registered):
    path = write(tmp_path, f"""
[[detectors]]
name = "hsom"
[[detectors]]
name = "no-such-detector"
optional = true
[[tasks]]
name = "{toy_registered.TASK}"
[[tasks]]
name = "no-such-task"
optional = true
""")
    suite = load_suite(path)
    assert [d.name for d in suite.detectors] == ["hsom"]
    assert suite.skipped == ["no-such-detector", "no-such-task"]


@pytest.mark.parametrize("body, message", [
    ('[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"\nnope = 1', "unknown key 'nope'"),
    ('[[detectors]]\nname = "hsomm"\n[[tasks]]\nname = "TASK"', "Unknown detector 'hsomm'. Did you mean 'hsom'"),
    ('[[detectors]]\nname = "hsom"\nparams = { n_row = 3 }\n[[tasks]]\nname = "TASK"', "did you mean 'n_rows'"),
    ('[[detectors]]\nname = "hsom"\nparams = { n_rows = 0 }\n[[tasks]]\nname = "TASK"', "must be an int in [1, inf)"),
    ('[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "no-such-task"', "Unknown dataset 'no-such-task'"),
    ('[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"\noptions = { n_tset = 3 }', "did you mean 'n_test'"),
    ('[[detectors]]\nname = "hsom"\ngrid = { alpha = 1.2 }\n[[tasks]]\nname = "TASK"', "must be a non-empty array"),
    ('[[detectors]]\nname = "hsom"\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"', "distinct 'label'"),
    ('[[tasks]]\nname = "TASK"', "has no detectors"),
    ('[[detectors]]\nname = "hsom"', "has no tasks"),
    ('[suite]\nseeds = [-1]\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"', "non-negative integers"),
    ('[suite]\nthreshold = 2\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"', "quantile in (0, 1]"),
    ('[suite]\nreference = "parzen"\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"',
     "reference 'parzen' is not a detector of suite 'suite.toml'; expected one of hsom"),
    ('[suite]\nreference = 3\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "TASK"', "a detector's label"),
    ('detectors = "hsom"', "array of tables"),
    ('[[detectors]\nname = "hsom"', "not valid TOML"),
])
def test_bad_suites_are_refused_with_one_clear_line(tmp_path, toy_registered, body, message):
    path = write(tmp_path, body.replace("TASK", toy_registered.TASK))
    with pytest.raises(SuiteError) as info:
        load_suite(path)
    text = str(info.value)
    assert message in text and "\n" not in text.strip()


def test_the_reference_detector_by_label(tmp_path, toy_registered):
    path = write(tmp_path, f"""
[suite]
reference = "small"
[[detectors]]
name = "hsom"
label = "small"
params = {{ n_rows = 3 }}
[[detectors]]
name = "parzen"
[[tasks]]
name = "{toy_registered.TASK}"
""")
    assert load_suite(path).reference == "small"


def test_a_missing_suite_file():
    with pytest.raises(SuiteError, match="Suite file not found"):
        load_suite("no/such/suite.toml")


def test_the_embedded_quick_suite_reads():
    import tomllib

    from novelty.datasets import registry as datasets

    assert quick_suite_path().is_file()
    tasks = [t["name"] for t in tomllib.loads(quick_suite_path().read_text())["tasks"]]
    assert all(t in datasets for t in tasks), f"the quick suite's tasks {tasks} must be registered"
    suite = load_suite(quick_suite_path())  # optional entries are skipped where absent
    assert suite.name == "quick"
    assert isinstance(suite, Suite)


def test_the_example_suites_read():
    """Every suite in benchmarks/suites names registered things (once they are all registered)."""
    from novelty.datasets import registry as datasets

    root = Path(__file__).resolve().parents[2] / "benchmarks" / "suites"
    paths = sorted(root.glob("*.toml"))
    if not paths:
        pytest.skip("benchmarks/suites is not part of this installation")
    for path in paths:
        import tomllib

        tasks = [t["name"] for t in tomllib.loads(path.read_text()).get("tasks", [])]
        missing = [t for t in tasks if t not in datasets]
        if missing:  # a suite may name tasks a plugin registers
            continue
        assert load_suite(path).cells(), path.name


def test_a_task_from_the_users_file_by_path_relative_to_the_suite(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "scans.csv").write_text("a,y\n1,0\n2,0\n3,1\n4,0\n")
    suite = load_suite(write(tmp_path, """
[[detectors]]
name = "hsom"

[[tasks]]
path = "data/scans.csv"
options = { train_rows = 2 }

[[tasks]]
name = "files"
label = "same"
options = { path = "data/scans.csv", train_rows = 2 }
"""))
    expected = str(tmp_path / "data" / "scans.csv")
    assert [(t.name, t.label, t.options) for t in suite.tasks] == [
        ("files", "scans", {"path": expected, "train_rows": 2}),
        ("files", "same", {"path": expected, "train_rows": 2})]


def test_a_recordings_files_are_read_relative_to_the_suite_too(tmp_path, monkeypatch):
    suite_path = write(tmp_path, """
[[detectors]]
name = "hsom"

[[tasks]]
name = "recording"
options = { paths = "mon.bag,tue.bag", marks = "marks.csv", places = 1.0 }

[[tasks]]
name = "recording"
label = "listed"
options = { paths = ["mon.bag", "/abs/tue.bag"], places = 1.0 }

[[tasks]]
name = "inspection-objects"
options = { path = "run.log", objects = "objects.toml", learn = 0.5 }

[[tasks]]
name = "exploration-objects"
options = { path = "run.log", n_objects = 2 }
""")
    monkeypatch.chdir(tmp_path.parent)              # run from elsewhere: the files stay the suite's
    options = [t.options for t in load_suite(suite_path).tasks]
    assert options == [
        {"paths": f"{tmp_path / 'mon.bag'},{tmp_path / 'tue.bag'}", "marks": str(tmp_path / "marks.csv"),
         "places": 1.0},
        {"paths": [str(tmp_path / "mon.bag"), "/abs/tue.bag"], "places": 1.0},
        {"path": str(tmp_path / "run.log"), "objects": str(tmp_path / "objects.toml"), "learn": 0.5},
        {"path": str(tmp_path / "run.log"), "n_objects": 2}]


@pytest.mark.parametrize("task, message", [
    ('path = "missing.csv"', "Data file not found: .*missing.csv"),
    ('name = "files"', "the 'files' task needs path="),
    ('name = "uci-sonar"\npath = "x.csv"', "a task with a 'path' is the 'files' task; got name 'uci-sonar'"),
])
def test_a_files_task_without_its_file_is_refused_before_running(tmp_path, task, message):
    with pytest.raises(SuiteError, match=message):
        load_suite(write(tmp_path, f'[[detectors]]\nname = "hsom"\n[[tasks]]\n{task}\n'))


@pytest.mark.parametrize("options, message", [
    ('label = "nove", train_rows = 2', r"Task 'scans': label: no column 'nove'; the file has a, novel\."),
    ('label = "novel", columns = "b"', r"Task 'scans': columns: no column 'b'; the file has a, novel\."),
    ('label = "novel", split = "part"', r"Task 'scans': split: no column 'part'"),
    ('label = "novel"', r"Task 'scans': .*how are the scans split into training and test\?"),
    ('label = "novel", train_rows = 9', r"Task 'scans': train_rows must leave scans on both sides: 1 to 3 of 4"),
])
def test_a_files_task_that_cannot_load_is_refused_before_running(tmp_path, options, message):
    """The messages of read_scans (as novelty run prints them), with the task's label."""
    (tmp_path / "scans.csv").write_text("a,novel\n0.1,0\n0.2,0\n0.3,0\n0.9,1\n")
    with pytest.raises(SuiteError, match=message):
        load_suite(write(tmp_path, f'[[detectors]]\nname = "hsom"\n[[tasks]]\npath = "scans.csv"\n'
                                   f'options = {{ {options} }}\n'))


@pytest.mark.parametrize("entry, message", [
    ('[[detectors]]\nname = "hsom"\nlabel = 5\n[[tasks]]\nname = "inspection-easy"\n',
     r"suite.toml: detectors\[0\]: label must be a non-empty string; got 5"),
    ('[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "inspection-easy"\nlabel = ["a"]\n',
     r"suite.toml: tasks\[0\]: label must be a non-empty string; got \['a'\]"),
    ('[[detectors]]\nname = "hsom"\nparams = { random_state = "abc" }\n[[tasks]]\nname = "inspection-easy"\n',
     r"Detector 'hsom': random_state must be None or an int seed in \[0, 2\*\*32\); got 'abc'"),
    ('[[detectors]]\nname = "gng-stanley"\nparams = { random_state = -1 }\n'
     '[[tasks]]\nname = "inspection-easy"\n', r"random_state must be None or an int seed"),
    ('[suite]\ncell_timeout = 0\n[[detectors]]\nname = "hsom"\n[[tasks]]\nname = "inspection-easy"\n',
     r"cell_timeout must be a positive number of seconds; got 0"),
])
def test_bad_fields_are_named(tmp_path, entry, message):
    with pytest.raises(SuiteError, match=message):
        load_suite(write(tmp_path, entry))


def test_a_suite_file_that_is_not_utf8_is_named(tmp_path):
    path = tmp_path / "suite.toml"
    path.write_bytes(b'[[detectors]]\nname = "h\xffsom"\n')
    with pytest.raises(SuiteError, match=rf"Suite file {path} is not UTF-8 text"):
        load_suite(path)


def test_a_detector_skipped_for_a_missing_extra_is_announced_with_the_extra(tmp_path, toy_registered, monkeypatch):
    monkeypatch.setattr(river, "installed", lambda: False)
    suite = load_suite(write(tmp_path, f"""
[[detectors]]
name = "hsom"
params = {{ n_rows = 2, n_columns = 2 }}
[[detectors]]
name = "river-hst"
optional = true
[[detectors]]
name = "river-loda"
optional = true
[[detectors]]
name = "no-such-detector"
optional = true
[[tasks]]
name = "{toy_registered.TASK}"
"""))
    console = io.StringIO()
    report = run_bench(suite, tmp_path / "out", plots=False, progress=console)
    notice = "Skipped river-hst, river-loda: River is not installed (pip install 'novelty-habituation[river]')."
    assert notice in console.getvalue()
    assert "Skipped no-such-detector: not registered here." in console.getvalue()
    assert notice in report.notes and notice in (tmp_path / "out" / "summary.md").read_text()


def test_a_suite_nested_thousands_deep_is_a_suite_error(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text("x = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(SuiteError, match="nests its tables or arrays too deeply"):
        load_suite(path)


def test_a_detector_that_reads_the_points_input_gets_it_from_a_task_that_can_give_it(tmp_path):
    path = write(tmp_path, """
[suite]
name = "layouts"
seeds = [0]

[[detectors]]
name = "map-explore"

[[detectors]]
name = "kmeans-stanley"

[[tasks]]
name = "inspection-easy"

[[tasks]]
name = "paper-a-to-b"
options = { inputs = "ring" }

[[tasks]]
name = "uci-sonar-mines"
""")
    cells = {(c.detector.label, c.task.label): c.task for c in load_suite(path).cells()}
    # the map reads the points input: the task that offers it gives it, under the same label
    assert cells["map-explore", "inspection-easy"].options == {"inputs": "points"}
    assert cells["kmeans-stanley", "inspection-easy"].options == {}
    # what the suite says is kept, and a task without the option is left as it is
    assert cells["map-explore", "paper-a-to-b"].options == {"inputs": "ring"}
    assert cells["map-explore", "uci-sonar-mines"].options == {}
    assert len({t.label for t in cells.values()}) == 3
