"""``novelty node`` without ROS: its help, and one line saying what to install."""

import sys

from novelty.cli import main


def test_without_rospy_the_command_says_what_to_install(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "rospy", None)   # import rospy raises ImportError
    monkeypatch.delitem(sys.modules, "novelty.rosnode.node", raising=False)
    assert main(["node", "_detector:=hsom"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("novelty node: error: novelty node needs ROS 1's rospy")
    assert "apt-get install ros-core python3-rospy" in err[0] and "--system-site-packages" in err[0]


def test_its_help_names_the_parameters_topics_and_services(capsys):
    assert main(["node", "--help"]) == 0
    out = capsys.readouterr().out
    for name in ("~detector", "~model", "~save", "scan:=/front/scan", "~novelty_stamped", "~set_learning",
                 "/use_sim_time", "status 2"):
        assert name in out, name
