"""Hostile files and streams around the detectors: save targets that are not regular files, suites
nested without end, and bytes of any kind on standard input.

Each case must end in the library's own error (a ``ValueError`` or an ``OSError`` subclass that says
what was expected) or in a result, never in another exception, a hang or a replaced target. The
examples are drawn from a fixed seed (``derandomize``), so CI runs the same few dozen every time.
"""

from __future__ import annotations

import io
import os
import socket
import stat

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import novelty
from novelty.bench import SuiteError, load_suite
from novelty.io.tables.stream import StreamReader

def fixed(examples: int):
    return settings(derandomize=True, database=None, deadline=None, max_examples=examples,
                    suppress_health_check=list(HealthCheck))


def _socket(path):
    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(path))
    sock.close()


def _device(path):
    os.mknod(path, 0o600 | stat.S_IFCHR, os.makedev(1, 3))


TARGETS = {"fifo": os.mkfifo, "directory": os.mkdir, "socket": _socket, "device": _device,
           "symlink": lambda path: os.symlink(path.parent / "elsewhere", path)}


@pytest.fixture(scope="module")
def model():
    return novelty.make("hsom", n_rows=2, n_columns=2).fit(np.random.default_rng(0).uniform(size=(10, 3)))


@pytest.mark.parametrize("kind", sorted(TARGETS))
def test_save_over_a_target_that_is_not_a_regular_file_refuses_and_leaves_it(model, tmp_path, kind):
    target = tmp_path / "model.npz"
    try:
        TARGETS[kind](target)
    except PermissionError:
        pytest.skip(f"making a {kind} needs privileges")
    before = os.lstat(target)
    with pytest.raises(FileExistsError, match="only a regular file is replaced"):
        model.save(target)
    after = os.lstat(target)
    assert (after.st_ino, after.st_mode) == (before.st_ino, before.st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.npz"]  # no temporary file left


def nested(draw_depth: int, kind: str) -> str:
    if kind == "array":
        return "x = " + "[" * draw_depth + "]" * draw_depth + "\n"
    return "x = " + "{ a = " * draw_depth + "1" + " }" * draw_depth + "\n"


@fixed(12)
@given(depth=st.sampled_from([1, 10, 100, 999, 1_000, 5_000, 50_000]), kind=st.sampled_from(["array", "table"]))
def test_a_nested_suite_is_a_suite_error(tmp_path_factory, depth, kind):
    path = tmp_path_factory.mktemp("suite") / "deep.toml"
    path.write_text(nested(depth, kind))
    with pytest.raises(SuiteError):  # too deep to read, or no detectors and tasks at the top
        load_suite(path)


@fixed(40)
@given(st.binary(max_size=300) | st.sampled_from([b"a,b\n\x00\x00\n", b"\xff\xfe\xfd\n", b"1,2\n" * 3 + b"\x80,1\n",
                                                  b"a,b\n" + b"9" * 10_000 + b",1\n", b'"unclosed,1\n2,3\n']))
def test_any_bytes_on_standard_input_give_scans_or_a_value_error(data):
    text = io.StringIO(data.decode("utf-8", errors="surrogateescape"), newline="")
    det = novelty.make("hsom", n_rows=2, n_columns=2)
    try:
        for x, _ in StreamReader(text):
            det.score_learn_one(x)
    except ValueError as exc:  # what the reader refuses, said (novelty run shows it as its own error)
        assert str(exc)
