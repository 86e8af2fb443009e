"""NOVELTY_NO_KERNELS read through the environment's own mapping, or through os.environ when that
mapping is not what it should be (novelty._kernels.environment)."""

from __future__ import annotations

import os

import pytest

from novelty._kernels import environment


class _Environ(dict):
    """An environment whose private mapping is given: os.environ's shape, another's contents."""

    def __init__(self, shown, data):
        super().__init__(shown)
        self._data = data
        self.encodekey = self.encodevalue = str.encode
        self.decodevalue = bytes.decode


def test_the_mapping_is_used_only_when_it_holds_what_the_environment_shows():
    assert _own_mapping_of({"A": "1"}, {b"A": b"1"}) == {b"A": b"1"}
    assert _own_mapping_of({"A": "1"}, {b"A": b"0"}) is None  # another value
    assert _own_mapping_of({"A": "1"}, {b"B": b"1"}) is None  # another name
    assert _own_mapping_of({"A": "1"}, {b"A": b"1", b"B": b"2"}) is None  # one more
    assert _own_mapping_of({"A": "1"}, [(b"A", b"1")]) is None  # not a mapping
    assert environment._own_mapping(dict(A="1")) is None  # no private mapping at all


def _own_mapping_of(shown, data):
    return environment._own_mapping(_Environ(shown, data))


@pytest.mark.parametrize("through_the_mapping", [True, False])
def test_disabled_follows_the_variable(monkeypatch, through_the_mapping):
    if through_the_mapping:
        assert environment._ENVIRON is not None  # CPython's os.environ passes the check
    else:
        monkeypatch.setattr(environment, "_ENVIRON", None)
    for value, expected in (("1", True), ("yes", True), ("0", False), ("", False)):
        monkeypatch.setenv("NOVELTY_NO_KERNELS", value)
        assert environment.disabled() is expected
    monkeypatch.delenv("NOVELTY_NO_KERNELS")
    assert environment.disabled() is False
    assert "NOVELTY_NO_KERNELS" not in os.environ
