"""A real ROS 1 master for the tests, on a free loopback port, and the processes that talk to it.

:class:`Master` starts ``roscore`` on a free port of 127.0.0.1 (never the
11311 of a user's own ROS), with ``ROS_HOME`` and ``ROS_LOG_DIR`` in the
test's folder, and stops it with every process it started (each in a
session of its own, stopped as a group). The node runs as ``python -m
novelty.cli node ...`` under this interpreter; bags are played with
``rosbag play`` and what the node publishes collected in the order it is
published (tests/rosnode/collect.py).
"""

import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client
from pathlib import Path

import pytest


def missing() -> str | None:
    """Why the ROS tests cannot run here, or None."""
    for tool in ("roscore", "rosbag", "rosparam", "rosservice"):
        if shutil.which(tool) is None:
            return f"ROS 1 is not installed ({tool} not on PATH; apt-get install ros-core python3-rospy ...)"
    try:
        import rospy  # noqa: F401
    except ImportError as exc:
        return f"rospy is not importable here ({exc}; a venv made with --system-site-packages sees Debian's)"
    return None


def skip_without_ros():
    reason = missing()
    if reason:
        pytest.skip(reason, allow_module_level=True)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Process:
    """A process in a session of its own (it and its children stopped together), its output in files."""

    def __init__(self, args, env, folder: Path, name: str):
        self.name, self.args = name, [str(a) for a in args]
        self.out, self.err = folder / f"{name}.out", folder / f"{name}.err"
        with open(self.out, "wb") as out, open(self.err, "wb") as err:
            self.popen = subprocess.Popen(self.args, env=env, stdout=out, stderr=err, start_new_session=True)

    def stop(self, sig=signal.SIGINT, timeout: float = 20.0) -> int:
        """Send ``sig`` to the process's group; wait for it (then SIGKILL); its exit status."""
        if self.popen.poll() is None:
            try:
                os.killpg(self.popen.pid, sig)
            except ProcessLookupError:
                pass
            try:
                self.popen.wait(timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.popen.pid, signal.SIGKILL)
                self.popen.wait()
        return self.popen.returncode

    def wait(self, timeout: float = 60.0) -> int:
        try:
            return self.popen.wait(timeout)
        except subprocess.TimeoutExpired:
            self.stop(signal.SIGKILL)
            raise AssertionError(f"{self.name} did not end within {timeout} s: {self.errors()}") from None

    def errors(self) -> str:
        return self.err.read_text(errors="replace") + self.out.read_text(errors="replace")


class Master:
    """``roscore`` on a free loopback port (see the module docstring)."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.port = free_port()
        self.uri = f"http://127.0.0.1:{self.port}/"
        home = folder / "ros_home"
        home.mkdir(parents=True, exist_ok=True)
        repository = Path(__file__).resolve().parents[2]   # the collector runs as tests.rosnode.collect
        self.env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(repository), os.environ.get("PYTHONPATH", "")]),
                    "ROS_MASTER_URI": self.uri, "ROS_HOME": str(home), "ROS_LOG_DIR": str(home / "log"),
                    "ROS_IP": "127.0.0.1", "PYTHONUNBUFFERED": "1"}
        self.env.pop("ROS_HOSTNAME", None)
        self.processes: list[Process] = []
        self.core = None

    def start(self) -> "Master":
        self.core = self.spawn(["roscore", "-p", self.port], "roscore")
        self.wait_until(self.online, 30, "the master to answer")
        return self

    def online(self) -> bool:
        try:
            code, _, _ = self.api().getPid("/tests")
            return code == 1
        except OSError:
            return False

    def api(self):
        return xmlrpc.client.ServerProxy(self.uri)

    def stop(self) -> None:
        for process in reversed(self.processes):
            process.stop()
        self.processes.clear()

    def spawn(self, args, name: str) -> Process:
        process = Process(args, self.env, self.folder, f"{name}-{len(self.processes)}")
        self.processes.append(process)
        return process

    def run(self, args, timeout: float = 60.0, check: bool = True) -> subprocess.CompletedProcess:
        done = subprocess.run([str(a) for a in args], env=self.env, capture_output=True, text=True, timeout=timeout)
        if check and done.returncode != 0:
            raise AssertionError(f"{' '.join(map(str, args))} exited {done.returncode}: {done.stderr}{done.stdout}")
        return done

    def node(self, *ros_args, name: str = "novelty") -> Process:
        """``novelty node ros_args... __name:=name``, under this interpreter."""
        return self.spawn([sys.executable, "-m", "novelty.cli", "node", *ros_args, f"__name:={name}"], name)

    def state(self) -> tuple:
        code, _, state = self.api().getSystemState("/tests")
        return state

    def subscribed(self, topic: str, node: str) -> bool:
        return any(t == topic and node in nodes for t, nodes in self.state()[1])

    def serves(self, service: str) -> bool:
        return any(s == service for s, _ in self.state()[2])

    def wait_for_node(self, process: Process, name: str = "/novelty", timeout: float = 60.0) -> None:
        """Until the node offers its services (it has read its parameters and subscribed)."""
        self.wait_until(lambda: self.serves(f"{name}/save") or process.popen.poll() is not None, timeout,
                        f"{name} to start")
        if process.popen.poll() is not None:
            raise AssertionError(f"{name} ended at start ({process.popen.returncode}): {process.errors()}")

    def record(self, out: Path, *topics: str) -> Process:
        """Collect what ``topics`` carry into ``out`` (tests/rosnode/collect.py), once subscribed to every one."""
        recorder = self.spawn([sys.executable, "-m", "tests.rosnode.collect", out, *topics, "__name:=recorder"],
                              "record")
        self.wait_until(lambda: all(self.subscribed(t, "/recorder") for t in topics), 30, "the recorder to subscribe")
        return recorder

    def play(self, bag: Path, *options, timeout: float = 120.0) -> None:
        """``rosbag play --clock`` of ``bag`` to its end."""
        self.run(["rosbag", "play", "--clock", "-q", *options, bag], timeout=timeout)

    @staticmethod
    def wait_until(condition, timeout: float, what: str, period: float = 0.1) -> None:
        end = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > end:
                raise AssertionError(f"timed out after {timeout} s waiting for {what}")
            time.sleep(period)


def recorded(path: Path) -> dict:
    """What :meth:`Master.record` collected: ``{topic: [message, ...]}`` in the order published."""
    from .collect import read

    return read(path)
