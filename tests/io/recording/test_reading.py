"""How a recording is read: the options object, checked once; as data and back; the old keywords."""

import inspect
import math
import warnings

import numpy as np
import pytest

from novelty import datasets
from novelty.io import Reading, read_recording, read_rings, read_sweeps
from novelty.io.frames.mounts import Mount
from novelty.io.recording.reading import RING_ONLY, mount_options, reading_given
from novelty.registry import InvalidParameterError
from novelty.tasks.recordings import recording_task

from ..carmen.test_log import LOG


@pytest.fixture
def carmen(tmp_path):
    path = tmp_path / "run.log"
    path.write_text(LOG)
    return path


def test_the_defaults_are_the_readers_defaults():
    reading = Reading()
    assert (reading.topic, reading.sectors, reading.reduce, reading.fragments, reading.echo) == (None, 16, "min",
                                                                                                   "auto", "first")
    assert (reading.tolerance, reading.fov, reading.threshold, reading.inputs) == (0.1, math.pi, 4.0, "ring")


@pytest.mark.parametrize("options, message", [
    (dict(echo="loudest"), "The 'echo' parameter of Reading must be one of 'first', 'last', 'strongest'. "
                           "Got 'loudest' instead."),
    (dict(sectors=0), "The 'sectors' parameter of Reading must be an int in [1, inf). Got 0 instead."),
    (dict(sectors=True), "The 'sectors' parameter of Reading must be an int in [1, inf). Got True instead."),
    (dict(reduce="max"), "The 'reduce' parameter of Reading must be one of 'min', 'mean', 'median' or a float "
                         "in [0, 100]. Got 'max' instead."),
    (dict(fragments=0), "The 'fragments' parameter of Reading must be one of 'auto' or an int in [1, inf). "
                        "Got 0 instead."),
    (dict(tolerance=-1.0), "The 'tolerance' parameter of Reading must be a float in [0, inf). Got -1.0 instead."),
    (dict(limits=(1.0, 0.0)), "The 'limits' parameter of Reading must be a pair (low, high) of radians"),
    (dict(topic=[]), "The 'topic' parameter of Reading must be a str, a non-empty sequence of str or None."),
    (dict(mounts="0,0"), "A mount is [TOPIC=]X,Y,YAW[,flipped]"),
    (dict(mounts=3), "The 'mounts' parameter of Reading must be a mount"),
    (dict(sensors={"s0": "left"}), "The 'sensors' parameter of Reading must be a sequence of sonar names"),
    (dict(threshold=0.0), "The 'threshold' parameter of Reading must be a float in (0, inf) or None. Got 0.0"),
    (dict(inputs="cloud"), "The 'inputs' parameter of Reading must be one of 'ring', 'points'. Got 'cloud'"),
    (dict(inputs="points", reduce="mean", clip=3.0), "The points input of Reading reads each sector's nearest echo "
                                                     "over the whole scan; clip, reduce apply to the ring only"),
])
def test_a_value_it_does_not_allow_is_refused_when_it_is_made(options, message):
    with pytest.raises(ValueError) as caught:
        Reading(**options)
    assert str(caught.value).startswith(message)


def test_the_ring_only_options_are_the_rings():
    assert set(RING_ONLY) == {"reduce", "limits", "front", "clip", "sensors", "max_span"}
    assert all(getattr(Reading(), k) == v for k, v in RING_ONLY.items())   # their defaults are the reading's


def test_it_is_frozen_and_its_sequences_are_tuples():
    reading = Reading(topic=["/a", "/b"], mounts={"/a": "0.2,0,0"}, sensors=["s1", "s0"], limits=[-1, 1])
    assert reading.topic == ("/a", "/b") and reading.topics == ["/a", "/b"]
    assert reading.mounts == ("/a=0.2,0,0",) and reading.sensors == ("s1", "s0") and reading.limits == (-1.0, 1.0)
    with pytest.raises(AttributeError):
        reading.sectors = 8
    assert hash(reading) == hash(Reading(topic=("/a", "/b"), mounts="/a=0.2,0,0", sensors=("s1", "s0"),
                                         limits=(-1.0, 1.0)))


def test_from_mapping_refuses_a_key_it_does_not_know_naming_those_it_does():
    with pytest.raises(ValueError, match=r"Unknown parameter 'sector' \(did you mean 'sectors'\?\) "
                                         r"for Reading\. Valid parameters: base_frame, clip, echo"):
        Reading.from_mapping({"sector": 8})
    with pytest.raises(ValueError, match="Unknown parameter 'report'"):
        Reading().replace(report=None)


def test_to_mapping_is_plain_data_that_from_mapping_reads_back():
    reading = Reading(topic=["/front", "/rear"], pose_topic="/odom", mounts=["/rear=-0.3,0,180,flipped"],
                      fragments=4, echo="last", sensors={"s0": 0.0, "s1": math.pi}, limits=(-1.5, 1.5), clip=3.0,
                      sectors=8, reduce=50.0, threshold=None, stamps=True)
    data = reading.to_mapping()
    assert data["topic"] == ["/front", "/rear"] and data["mounts"] == ["/rear=-0.3,0,180,flipped"]
    assert data["sensors"] == {"s0": 0.0, "s1": math.pi} and data["limits"] == [-1.5, 1.5]
    assert list(data) == list(Reading.fields())
    assert Reading.from_mapping(data) == reading
    assert Reading.from_mapping(Reading().to_mapping()) == Reading()


def test_a_mount_given_as_an_object_is_written_as_its_description():
    mount = Mount.planar(0.5, 0.0, 0.0)
    reading = Reading(mounts={"/scan": mount})
    assert reading.mounts == (("/scan", mount),)
    assert reading.to_mapping()["mounts"] == ["/scan: x=0.5 m, y=0 m, yaw=0 deg, from option"]
    assert reading.mount_map() == {"/scan": mount}


def test_mounts_as_text_object_or_dict_give_the_same_mounts():
    text = mount_options("/rear=-0.3,0,180")
    assert mount_options({"/rear": "-0.3,0,180"}) == text == Reading(mounts=["/rear=-0.3,0,180"]).mount_map()
    assert list(mount_options("0,0,90")) == [None]   # every topic's


def test_a_tasks_metadata_keeps_the_bag_options_given_otherwise_than_by_default():
    reading = Reading(mounts="/rear=-0.3,0,180,flipped", echo="last")
    assert reading_given(reading.fragments, reading.mounts, reading.echo) == {
        "mounts": {"/rear": "x=-0.3 m, y=0 m, yaw=180 deg, upside down, from option"}, "echo": "last"}
    assert reading_given() == {}


def test_every_reader_takes_one(carmen):
    reading = Reading(sectors=2)
    rings = [r.ranges.tolist() for r in read_rings(carmen, reading)]
    assert rings == read_recording(carmen, reading.replace(threshold=None)).X.tolist()
    assert len(list(read_sweeps(carmen, reading))) == len(rings)


def test_the_old_keywords_still_read_the_same_with_a_future_warning(carmen):
    new = [r.ranges for r in read_rings(carmen, Reading(topic="FLASER", sectors=2))]
    with pytest.warns(FutureWarning, match=r"read_rings\(path, topic=\.\.\., sectors=\.\.\.\) is deprecated .* "
                                           r"read_rings\(path, Reading\(topic=\.\.\., sectors=\.\.\.\)\)"):
        old = [r.ranges for r in read_rings(carmen, "FLASER", sectors=2)]
    assert np.array_equal(old, new)
    with pytest.warns(FutureWarning, match="read_recording"):
        assert read_recording(carmen, threshold=None, sectors=2).X.tolist() == np.array(new).tolist()
    with pytest.warns(FutureWarning, match="read_sweeps"):
        assert len(list(read_sweeps(carmen, fov=math.pi / 2))) == len(new)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        list(read_rings(carmen, Reading(sectors=2)))           # a Reading: no warning


def test_a_task_takes_its_options_one_by_one_as_a_suite_gives_them(carmen):
    signature = inspect.signature(recording_task).parameters
    assert set(Reading.fields()) <= set(signature) and "options" not in signature
    assert all(signature[k].default == getattr(Reading(), k) for k in Reading.fields())
    loose = recording_task([carmen, carmen], places=1.0, sectors=2)
    given = recording_task([carmen, carmen], Reading(sectors=2), places=1.0)
    assert np.array_equal(loose.X, given.X) and loose.metadata == given.metadata
    with pytest.raises(InvalidParameterError, match="Unknown parameter 'sector' .* for dataset 'recording'"):
        datasets.load("recording", paths=str(carmen), places=1.0, sector=2)
    with pytest.raises(ValueError, match="threshold must be a number of metres"):
        recording_task([carmen, carmen], places=1.0, threshold=None)
