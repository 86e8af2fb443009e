"""The README's Python examples run as written."""

import re
from pathlib import Path

import pytest

import novelty

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


#: blocks that are files (a first line ``# name.py``): written out, importable by the others
FILES = {m.group(1): b for b in BLOCKS if (m := re.match(r"# (\w+)\.py\n", b))}


def write_files(folder, monkeypatch) -> None:
    for name, block in FILES.items():
        (folder / f"{name}.py").write_text(block, encoding="utf-8")
    monkeypatch.syspath_prepend(str(folder))


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_python_block_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the examples write model files
    write_files(tmp_path, monkeypatch)
    names_before = set(novelty.registry.clusterers.names())
    try:
        exec(compile(BLOCKS[index], f"README.md[python block {index}]", "exec"), {})
    finally:
        for name in set(novelty.registry.clusterers.names()) - names_before:
            novelty.registry.clusterers.unregister(name)


def test_readme_custom_clusterer_passes_conformance():
    namespace = {}
    block = next(b for b in BLOCKS if "register_clusterer" in b)
    try:
        exec(block, namespace)
        from novelty.testing import check_conformance

        check_conformance(namespace["TinyKMeans"]())
        det = namespace["det"]
        import numpy as np

        out = det.stream(np.tile(np.full(16, 0.3), (5, 1)))
        assert out[0] == 1.0 and np.all(np.diff(out) < 0), "a repeated scan habituates"
    finally:
        novelty.registry.clusterers.unregister("tiny-kmeans")


def test_readme_own_data_commands_run_as_written(tmp_path, monkeypatch):
    import shlex
    import shutil

    from novelty.bench import load_suite
    from novelty.cli import main

    section = README.read_text(encoding="utf-8").split("## Your own data")[1].split("\n## ")[0]
    bash = re.findall(r"```bash\n(.*?)```", section, flags=re.S)
    toml = re.findall(r"```toml\n(.*?)```", section, flags=re.S)
    example = README.parent / "examples" / "own-data" / "corridor.csv"
    shutil.copy(example, tmp_path / "corridor.csv")
    monkeypatch.chdir(tmp_path)
    commands = [line for line in bash[0].replace("\\\n", " ").splitlines() if line.startswith("novelty ")]
    assert len(commands) == 2
    for command in commands:
        assert main(shlex.split(command)[1:] + ["--quiet"] * command.startswith("novelty bench")) == 0
    assert (tmp_path / "novelty.csv").read_text().startswith("scan,novelty,alarm,y,distance,time\n")
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
