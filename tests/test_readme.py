"""The README's checks beyond running its examples (``tests/test_docs.py`` runs every block).

The custom clusterer of the README and the synapse of the guide pass the
conformance suite; the own-data commands produce what the guide says; the
README's quickstart is what CI runs first.
"""

import re
import shlex
import shutil
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # the tomli backport, a dependency on 3.10
    import tomli as tomllib

import numpy as np
import pytest

import novelty
from novelty.bench import load_suite
from novelty.cli import main

README = Path(__file__).resolve().parents[1] / "README.md"
GUIDE = README.parent / "docs" / "guide"


def python_blocks(page: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), flags=re.S)


def test_readme_custom_clusterer_passes_conformance():
    namespace = {}
    block = next(b for b in python_blocks(README) if "register_clusterer" in b)
    try:
        exec(block, namespace)
        novelty.testing.check_conformance(namespace["TinyKMeans"]())  # batch scoring compiled, as match
        det = namespace["det"]
        out = det.stream(np.tile(np.full(16, 0.3), (5, 1)))
        assert out[0] == 1.0 and np.all(np.diff(out) < 0), "a repeated scan habituates"
    finally:
        novelty.registry.clusterers.unregister("tiny-kmeans")


def test_guide_fading_synapse_passes_conformance(tmp_path, monkeypatch):
    """The guide's synapse gives only its equation and its own parameter's rule: the schedule and
    its parameters are the base class's, so it passes every synapse check, the compiled one among
    them, whatever its gain."""
    block = next(b for b in python_blocks(GUIDE / "extending.md") if b.startswith("# fading.py"))
    (tmp_path / "fading.py").write_text(block, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "fading", raising=False)
    from fading import Fading

    novelty.testing.check_conformance(Fading())
    novelty.testing.check_conformance(Fading(gain=2.5, others="forget"))
    assert Fading(others="forget", tau_forget=20.0).get_params() == {
        "gain": 1.0, "tau_winner": 3.0, "tau_neighbour": 12.0, "others": "forget", "tau_forget": 20.0}
    with pytest.raises(ValueError, match="The 'gain' parameter of Fading must be a float in"):
        Fading(gain=0).initialize(3)
    with pytest.raises(ValueError, match="The 'others' parameter of Fading must be one of"):
        Fading(others="recover").initialize(3)


def test_guide_own_data_commands_run_as_written(tmp_path, monkeypatch):
    section = (GUIDE / "own-data.md").read_text(encoding="utf-8")
    bash = re.findall(r"```bash\n(.*?)```", section, flags=re.S)
    toml = re.findall(r"```toml\n(.*?)```", section, flags=re.S)
    example = README.parent / "examples" / "own-data" / "corridor.csv"
    shutil.copy(example, tmp_path / "corridor.csv")
    monkeypatch.chdir(tmp_path)
    commands = [line for line in bash[0].replace("\\\n", " ").splitlines() if line.startswith("novelty ")]
    assert len(commands) == 2
    for command in commands:
        assert main(shlex.split(command)[1:] + ["--quiet"] * command.startswith("novelty bench")) == 0
    assert (tmp_path / "novelty.csv").read_text().startswith("scan,novelty,alarm,threshold,y,distance,time\n")
    (tmp_path / "suite.toml").write_text('[[detectors]]\nname = "hsom"\n' + toml[0])
    assert load_suite(tmp_path / "suite.toml").tasks[0].options["path"] == str(tmp_path / "corridor.csv")


def quickstart_commands(text: str) -> list[str]:
    section = text.split("## Quickstart", 1)[1].split("\n## ", 1)[0]
    block = re.search(r"```bash\n(.*?)```", section, flags=re.S).group(1)
    return [line.strip() for line in block.splitlines() if line.strip()]


def test_ci_runs_the_readme_quickstart_first_as_written():
    readme = quickstart_commands(README.read_text(encoding="utf-8"))
    script = (README.parent / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    start, end = script.index("# >>> README quickstart"), script.index("# <<< README quickstart")
    assert [line.strip() for line in script[start + 1:end] if line.strip()] == readme
    before = [line for line in script[:start] if line.strip() and not line.lstrip().startswith("#")]
    # nothing installed or run before the quickstart but a fresh virtual environment
    assert not [line for line in before if re.search(r"\b(pip|pytest|novelty|sphinx)\b", line)], before
    assert any("-m venv" in line for line in before)


def test_ci_runs_the_tests_the_readme_leaves_out():
    # The README's pytest leaves out the tests marked slow (pyproject.toml's addopts); CI runs them
    # next, and the kernel checks (bounds checking, the newest numba) run every kernel test.
    options = tomllib.loads((README.parent / "pyproject.toml").read_text(encoding="utf-8"))
    addopts = shlex.split(options["tool"]["pytest"]["ini_options"]["addopts"])
    assert addopts[addopts.index("-m") + 1] == "not slow"
    script = (README.parent / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    end = script.index("# <<< README quickstart")
    assert "pytest -n auto -m slow" in [line.strip() for line in script[end:]]
    kernels = [line for line in script[end:] if line.rstrip().endswith("tests/_kernels")]
    assert kernels and all('-m ""' in line for line in kernels), kernels
    assert "pytest -n auto -m slow" in README.read_text(encoding="utf-8")


def test_the_site_opens_with_the_readme_quickstart_and_its_cost():
    # The site's front door: its first command works from a checkout (the README's two, as CI
    # runs them), says what each costs in time, and names the published install as future.
    index = (README.parent / "docs" / "index.md").read_text(encoding="utf-8")
    first = re.search(r"```bash\n(.*?)```", index, flags=re.S)
    commands = [line.strip() for line in first.group(1).splitlines() if line.strip()]
    assert commands == quickstart_commands(README.read_text(encoding="utf-8"))
    after = index[first.end():].split("\n\n", 2)
    cost = " ".join(after[:2])
    assert re.search(r"\d+ (s|min)", cost) and "first time" in cost and "test suite" in cost, cost
    published = index[:first.start()]
    assert "novelty-habituation[all]" in published and "once it is" in published


def test_the_readme_stays_a_front_page():
    # Studies, tables and long explanations belong in the guide (docs/guide/), linked from the README.
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 250, f"README.md has {len(lines)} lines; move the detail to a page of docs/guide/"
    for page in re.findall(r"\]\((docs/[^)#]+)", "\n".join(lines)):
        assert (README.parent / page).exists(), f"the README links to {page}, which does not exist"


def test_pytest_configuration_names_no_novelty_class():
    # pytest imports the classes of pyproject's filterwarnings before the checkout is on the path:
    # after `pip install .`, `pytest` would import the installed novelty and refuse to collect the
    # checkout's modules (import file mismatch), failing the README's second command.
    options = tomllib.loads((README.parent / "pyproject.toml").read_text(encoding="utf-8"))
    pytest_options = options["tool"]["pytest"]["ini_options"]
    named = [f for f in pytest_options.get("filterwarnings", []) if "novelty" in f]
    assert not named, f"filter these in conftest.py instead: {named}"
