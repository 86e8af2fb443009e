"""The node's parameters: read as ROS gives them (YAML types), checked in the project's message form."""

import math

import pytest

from novelty.rosnode.settings import PARAMETERS, Settings, SettingsError


def test_the_defaults_are_novelty_runs():
    s = Settings.read({"detector": "hsom"})
    assert (s.fragments, s.echo, s.tolerance, s.sectors, s.reduce, s.limits, s.front) == \
        ("auto", "first", 0.1, None, "min", None, 0.0)
    assert (s.range_threshold, s.stamps, s.alarm, s.learning, s.transform_timeout) == (4.0, False, "threshold", True, 1.0)
    assert s.scan_topics == () and s.mounts == () and s.params == {}


def test_values_as_yaml_and_the_command_line_give_them():
    s = Settings.read({"detector": "map-explore", "params": {"cell_size": 0.2, "top": 3}, "sectors": 90,
                       "scan_topics": "/front/scan, /rear/scan", "mounts": {"/rear/scan": "-0.3,0,180,flipped"},
                       "limits": "-90,90", "front": 10, "stamps": True, "fragments": 1, "reduce": 25})
    assert s.params == {"cell_size": 0.2, "top": 3} and s.sectors == 90
    assert s.scan_topics == ("/front/scan", "/rear/scan") and s.mounts == ("/rear/scan=-0.3,0,180,flipped",)
    assert s.limits == (-90.0, 90.0) and s.limits_radians == (-math.pi / 2, math.pi / 2)
    assert s.front == 10.0 and isinstance(s.front, float) and s.stamps and s.fragments == 1 and s.reduce == 25


@pytest.mark.parametrize("given, message", [
    ({"sectors": 0}, "The '~sectors' parameter of the novelty node must be an int in [1, inf). Got 0 instead."),
    ({"sectors": 2.5}, "The '~sectors' parameter of the novelty node must be an int in [1, inf). Got 2.5 instead."),
    ({"stamps": "yes"}, "The '~stamps' parameter of the novelty node must be true or false. Got 'yes' instead."),
    ({"echo": "middle"}, "The '~echo' parameter of the novelty node must be one of 'first', 'last', 'strongest'. "
                         "Got 'middle' instead."),
    ({"fragments": 0}, "The '~fragments' parameter of the novelty node must be 'auto' or an int in [1, inf). "
                       "Got 0 instead."),
    ({"limits": [90, -90]}, "The '~limits' parameter of the novelty node must be a pair [LOW, HIGH] of degrees in "
                            "[-360, 360] with LOW < HIGH. Got [90, -90] instead."),
    ({"range_threshold": 0}, "The '~range_threshold' parameter of the novelty node must be a float in (0, inf). "
                             "Got 0 instead."),
    ({"queue_size": True}, "The '~queue_size' parameter of the novelty node must be an int in [1, inf). "
                           "Got True instead."),
    ({"params": [1, 2]}, "The '~params' parameter of the novelty node must be a mapping of the detector's "
                         "parameters (YAML: {n_rows: 5, alpha: 1.2}). Got [1, 2] instead."),
    ({"mounts": ["/rear=x,0,0"]}, "~mounts: A mount is [TOPIC=]X,Y,YAW[,flipped] (m, m, degrees); got '/rear=x,0,0'."),
    ({"alarm": "k-of-n:3"}, "~alarm: Alarm 'k-of-n:3' takes k-of-n:K,N[,T]; got 1 value."),
    ({"scan_topic": "/scan"}, "Unknown parameter ~scan_topic of the novelty node; its parameters: ~detector, "),
])
def test_a_parameter_out_of_its_range_is_named_with_what_it_takes(given, message):
    with pytest.raises(SettingsError) as err:
        Settings.read({"detector": "hsom", **given})
    assert str(err.value).startswith(message)


def test_a_detector_or_a_model():
    with pytest.raises(SettingsError, match=r"Give the novelty node ~detector \(a registered name: novelty list "
                                            r"detectors\) or ~model \(a saved model to continue from\)."):
        Settings.read({})
    # a node started again with a model keeps the master's parameters of its first start: they are not used
    s = Settings.read({"detector": "hsom", "params": {"n_rows": 3}, "model": "m.npz"})
    assert s.unused == ["~detector", "~params"] and Settings.read({"model": "m.npz"}).unused == []


def test_every_parameter_is_a_field_and_has_a_check():
    assert list(PARAMETERS) == [f for f in Settings.__dataclass_fields__]
