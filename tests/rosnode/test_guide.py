"""The guide page "On a live robot" run as written, against a real ROS master.

The page's blocks that need a master say so (``<!-- not run: needs a ROS
master; tests/rosnode/test_guide.py runs ... -->``): the docs test leaves
them to this one, which runs them in order in one folder (a copy of the
repository's ``ros/``, and ``robot.bag``: two loops of a robot round a room,
a box standing by the way on the second), each bash block in a shell of its
own whose background processes (roslaunch, rostopic) live on until the end,
each Python block as the docs test runs it. What a block prints is compared
with what the page says it prints; then what the session left (the novelty
published, the saved model, the rings of the pipe) is checked against
``novelty run`` on the same bag.

``NOVELTY_GUIDE_FIGURE=docs/live-robot-novelty.png`` copies the session's
figure there (how the page's figure was made).
"""

import csv
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import novelty
from novelty.cli import main
from novelty.io.ros.caps import Where
from novelty.io.ros.decoders import decode
from novelty.sonar import preprocess

from ..test_docs import blocks, output_problems, run_block
from .ros import Master, skip_without_ros

skip_without_ros()
pytest.importorskip("rosbags", reason="the bags are written with rosbags' writers (the ros extra)")
pytest.importorskip("matplotlib", reason="the page draws the novelty published (the plot extra)")

from .bags import messages, two_loops  # noqa: E402

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "guide" / "live-robot.md"
MINE = "tests/rosnode/test_guide.py"


def session_blocks() -> list[dict]:
    return [b for b in blocks(PAGE) if b["reason"] and MINE in b["reason"]]


def test_the_page_gives_this_test_its_session():
    langs = [b["lang"] for b in session_blocks()]
    assert langs == ["bash", "bash", "python", "bash", "bash"], langs


def test_the_guides_session_runs_as_written_against_a_real_master(tmp_path):
    where = tmp_path / "session"
    where.mkdir()
    shutil.copytree(ROOT / "ros", where / "ros")
    bag = two_loops(where / "robot.bag")
    master = Master(tmp_path).start()
    env = _environment(master, where)
    groups = []
    try:
        for block in session_blocks():
            if block["lang"] == "bash":
                done = _bash(block["code"], where, env, groups)
            else:
                done = run_block(block, where, env)
            assert done.returncode == 0, f"block {block['index']} failed:\n{block['code']}\n{done.stderr[-3000:]}"
            problems = output_problems(block, done)
            assert not problems, f"block {block['index']}:\n" + "\n".join(problems)
            if "rosnode kill" in block["code"]:
                # the model the node saved as it stopped: the two loops it learned, scan for scan
                assert novelty.load(where / "map.npz").clusterer_.scans_ == 800
    finally:
        for group in groups:
            _stop(group)
        master.stop()
    _check_the_session(where, bag, tmp_path)


def _environment(master: Master, where: Path) -> dict:
    """The master's, with ``novelty`` on the path as a user's install puts it (this checkout's)."""
    bin_dir = where.parent / f"{where.name}-bin"   # where the docs test's runner keeps a Python block's files
    bin_dir.mkdir()
    shim = bin_dir / "novelty"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m novelty.cli "$@"\n')
    shim.chmod(0o755)
    return {**master.env, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg",
            "PATH": os.pathsep.join([str(bin_dir), str(Path(sys.executable).parent), os.environ.get("PATH", "")])}


def _bash(code: str, where: Path, env: dict, groups: list) -> subprocess.CompletedProcess:
    """Run ``code`` in a shell of its own session; its background processes are stopped at the end.

    The variables exported by the blocks before are exported again first, as in the one terminal a user
    types the page's blocks into.
    """
    state = where.parent / f"{where.name}-bin" / "exported.sh"
    code = f"[ -f {state} ] && . {state}\n{code}\nexport -p > {state}\n"
    process = subprocess.Popen(["bash", "-e", "-o", "pipefail", "-c", code], cwd=where, env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    groups.append(process.pid)
    stdout, stderr = process.communicate(timeout=300)
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)


def _stop(group: int) -> None:
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(group, sig)
        except ProcessLookupError:
            return
        for _ in range(100):
            try:
                os.killpg(group, 0)
            except ProcessLookupError:
                return
            signal.sigtimedwait([], 0.1) if hasattr(signal, "sigtimedwait") else None


def _check_the_session(where: Path, bag: Path, tmp_path: Path) -> None:
    # the novelty published is novelty run's on the bag, with the options of the package's YAML
    out = tmp_path / "offline.npz"
    assert main(["run", "map-explore", "--data", str(bag), "--fragments", "1", "--out", str(out)]) == 0
    expected = np.load(out)["novelty"]
    with open(where / "published.csv") as fh:
        published = [float(row["field.vector.x"]) for row in csv.DictReader(fh)]
    np.testing.assert_array_equal(published, expected)
    # the node started again from it went on learning (the pipe's scans), and saved as it stopped
    assert novelty.load(where / "map.npz").clusterer_.scans_ > 800
    # the pipe's rings: gwr-explore-wang-hsu (the answer without a pose) on 20 consecutive scans' ranges,
    # preprocessed as the paper's
    with open(where / "rings.csv") as fh:
        rings = list(csv.DictReader(fh))
    assert len(rings) == 20
    scans = [(record, data) for topic, _, record, data in messages(bag) if topic == "/scan"]
    first = int(np.argmin([abs(record - float(rings[0]["time"])) for record, _ in scans]))
    ranges = np.array([decode("sensor_msgs/msg/LaserScan", data, True, Where("bag", "/scan", i), "/scan").ranges
                       for i, (_, data) in enumerate(scans[first:first + 20])])
    # rostopic's %time column (its arrival time, ns) is read as the scans' times: the synapses' elapsed time
    streamed = novelty.make("gwr-explore-wang-hsu").stream(preprocess(ranges, 4.0),
                                                           timestamps=[float(r["time"]) for r in rings])
    np.testing.assert_allclose([float(r["novelty"]) for r in rings], streamed, rtol=1e-9)
    figure = os.environ.get("NOVELTY_GUIDE_FIGURE")
    if figure:
        shutil.copy(where / "live-novelty.png", figure)
