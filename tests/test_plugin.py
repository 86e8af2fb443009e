"""The example plugin package: its clusterer in 'novelty list' and inside a benchmark run.

The package is made visible to a fresh interpreter as an installed
distribution would be (a ``.dist-info`` with ``entry_points.txt`` on the
path), without pip: the same mechanism ``pip install`` sets up.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import novelty

ROOT = Path(novelty.__file__).resolve().parents[1]
PLUGIN = ROOT / "examples" / "novelty-plugin-example"


@pytest.fixture
def plugin_env(tmp_path):
    if not PLUGIN.is_dir():
        pytest.skip("the examples folder is not part of this installation")
    dist = tmp_path / "novelty_plugin_example-0.1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: novelty-plugin-example\nVersion: 0.1.0\n")
    # the example's own entry point, plus the toy task so the run needs no simulator
    pyproject = (PLUGIN / "pyproject.toml").read_text()
    assert 'leader = "novelty_plugin_example:LeaderClusterer"' in pyproject
    (dist / "entry_points.txt").write_text(
        "[novelty.clusterers]\nleader = novelty_plugin_example:LeaderClusterer\n\n"
        "[novelty.datasets]\nbench-toy-task = toy:toy_task\n")
    path = os.pathsep.join([str(tmp_path), str(PLUGIN / "src"), str(Path(__file__).parent / "bench"), str(ROOT)])
    return {**os.environ, "PYTHONPATH": path, "CI": "true"}


def cli(env, *args):
    return subprocess.run([sys.executable, "-m", "novelty.cli", *args], capture_output=True, text=True,
                          env=env, timeout=180)


def test_the_plugin_clusterer_is_listed_and_benchmarked(plugin_env, tmp_path):
    listed = cli(plugin_env, "list", "clusterers")
    assert listed.returncode == 0, listed.stderr
    assert "leader" in listed.stdout and "Hartigan's leader clusterer" in listed.stdout
    out = tmp_path / "bench"
    run = cli(plugin_env, "bench", "--detector", "habituating clusterer=leader radius=0.05",
              "--detector", "hsom", "--task", "bench-toy-task", "--seeds", "2",
              "--out", str(out), "--no-plots")
    assert run.returncode == 0, run.stderr
    assert "habituating[clusterer=leader,radius=0.05]" in run.stdout
    rows = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    leader = [r for r in rows if "leader" in r["detector"]]
    assert len(leader) == 2, rows
    assert all(r["status"] == "ok" for r in leader), [r["error"] for r in leader]
    assert all(r["n_units"] > 1 for r in leader), [r["n_units"] for r in leader]
