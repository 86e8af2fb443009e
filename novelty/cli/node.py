"""``novelty node``: the live ROS 1 node, scoring each scan as it arrives.

Shares its name with novelty/rosnode/node.py: a command's module is named after the command, and
that is the node it starts.
"""

from __future__ import annotations

import argparse

from ._common import UserError, add_command

DESCRIPTION = """Run a ROS 1 node that scores each scan as it arrives, learns it, and publishes its novelty.

The scans are read as 'novelty run' reads a bag (fragments assembled,
sensors placed by tf or ~mounts, several lasers merged, poses from tf at
each scan's time), and scored then learned by the same detector: a bag
played with 'rosbag play' gives the node the novelty 'novelty run' writes
for the bag, scan for scan. Needs ROS 1's rospy under the system Python
(Debian: apt-get install ros-core python3-rospy python3-tf2-ros ...) and
a virtual environment that sees it (python3 -m venv --system-site-packages).

Its parameters are private ROS parameters: from a YAML file (rosparam load,
a launch file) or the command line (_name:=value). ~detector (a registered
name) or ~model (a saved model to continue from); ~params (the detector's);
~save (where the model is saved, atomically, on shutdown and by ~save);
scans on the relative topic 'scan' (remap it: scan:=/front/scan) or
~scan_topics (several lasers, merged); ~pose_topic, ~base_frame,
~fixed_frame, ~mounts, ~fragments, ~echo, ~tolerance, ~sectors, ~reduce,
~limits, ~front, ~range_threshold, ~stamps as 'novelty run' on a recording;
~threshold, ~alarm; ~learning (false: start frozen); ~transform_timeout
(s a scan waits for its transforms); ~queue_size (scans waiting before the
oldest is dropped); ~stopped_after (s without a scan before the
diagnostics say they stopped). /use_sim_time is honoured.

Publishes ~novelty (std_msgs/Float32), ~novelty_stamped
(geometry_msgs/Vector3Stamped: x novelty, y alarm, z threshold, stamped with
the scan's time), ~alarm (std_msgs/Bool), ~novel_cells
(visualization_msgs/MarkerArray, for a map) and /diagnostics. Services:
~set_learning (std_srvs/SetBool), ~save and ~reset (std_srvs/Trigger).
A node that cannot start (no master, an unknown detector, a model that does
not load, a parameter out of range) exits with one line and status 2."""

EXAMPLES = [
    "novelty node _detector:=hsom _sectors:=16",
    "novelty node _detector:=map-explore scan:=/front/scan _save:=map.npz",
    "novelty node _model:=map.npz _save:=map.npz __name:=novelty_front",
    "rosparam load novelty.yaml /novelty && novelty node",
]


def add_parser(subparsers):
    parser = add_command(subparsers, "node", "run the live ROS 1 node: score, learn and publish each scan's novelty",
                         DESCRIPTION, EXAMPLES)
    parser.add_argument("ros_args", nargs=argparse.REMAINDER, metavar="NAME:=VALUE",
                        help="ROS arguments: private parameters (_detector:=hsom), remappings (scan:=/front/scan), "
                        "the node's name (__name:=novelty_front)")
    return parser


def run(args) -> int:
    try:
        # deferred: rospy is an optional dependency (ROS 1, under the system Python); the rest of the
        # command line works without it
        from ..rosnode.node import main
        from ..rosnode.setup import StartError
    except ImportError as exc:
        raise UserError(f"novelty node needs ROS 1's rospy and message packages ({exc}): apt-get install ros-core "
                        "python3-rospy python3-tf2-ros python3-sensor-msgs python3-nav-msgs python3-std-srvs "
                        "python3-diagnostic-msgs python3-visualization-msgs, and a virtual environment made with "
                        "'python3 -m venv --system-site-packages' (docs/guide/live-robot.md).") from None
    try:
        return main(args.ros_args)
    except StartError as exc:
        raise UserError(str(exc)) from None
