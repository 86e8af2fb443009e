"""Small bags written with rosbags' writers for the tests: ROS 1, ROS 2 SQLite and ROS 2 MCAP.

Each holds a laser (/scan: 4 beams over 180 degrees with +inf, NaN, -inf and
out-of-range readings), three sonars on one topic (/sonar, frames s0..s2)
and odometry (/odom). Scans at 1.0, 1.1, 1.2 s, then a gap to 6.0, 6.1 s; each message recorded a
microsecond after its header's stamp (so a test can tell the two apart).
"""

import dataclasses
import math
import shutil

import numpy as np

SCAN_TIMES = (1.0, 1.1, 1.2, 6.0, 6.1)
#: the laser's ranges at each scan (range_min 0.1, range_max 10)
SCAN_RANGES = [[1.0, math.inf, 2.0, 3.0], [math.nan, 1.5, -math.inf, 12.0]] + [[2.0, 2.0, 2.0, 2.0]] * 3
#: the three sonars' readings at each time (range 0.2..5), each frame in turn s2, s0, s1
SONAR = [(1.0, "s2", 3.0), (1.01, "s0", 1.0), (1.02, "s1", math.inf), (1.1, "s2", 4.0), (1.11, "s0", 2.0),
         (1.12, "s1", 0.5), (6.0, "s2", 1.0), (6.01, "s0", 9.0), (6.02, "s1", 1.0)]
#: odometry: x = t metres, heading 0.5 rad; tf at the same times: base_link at x = t + 10 in odom
#: (and the laser's frame at base_link's origin, facing forward)
ODOM_TIMES = (0.95, 1.15, 5.95)


def _stamp(ts, t):
    return ts.types["builtin_interfaces/msg/Time"](sec=int(t), nanosec=int(round((t % 1) * 1e9)))


def _make(ts, msgtype, **values):
    """A message of ``msgtype`` with ``values``; every other field a zero of its kind."""
    cls = ts.types[msgtype]
    for field in dataclasses.fields(cls):
        if field.name not in values:
            values[field.name] = 0 if field.name in ("seq", "radiation_type") else 0.0
    return cls(**values)


def _header(ts, t, frame):
    return _make(ts, "std_msgs/msg/Header", stamp=_stamp(ts, t), frame_id=frame)


def _messages(ts):
    """(time, topic, type, message) in time order."""
    out = []
    for t, ranges in zip(SCAN_TIMES, SCAN_RANGES):
        out.append((t, "/scan", "sensor_msgs/msg/LaserScan", _make(
            ts, "sensor_msgs/msg/LaserScan", header=_header(ts, t, "laser"), angle_min=-math.pi / 2,
            angle_max=math.pi / 2, angle_increment=math.pi / 3, range_min=0.1, range_max=10.0,
            ranges=np.array(ranges, dtype=np.float32), intensities=np.zeros(0, np.float32))))
    out.append((1.05, "/cloud", "sensor_msgs/msg/PointCloud2", _cloud(ts, 1.05)))
    for t, frame, r in SONAR:
        out.append((t, "/sonar", "sensor_msgs/msg/Range", _make(
            ts, "sensor_msgs/msg/Range", header=_header(ts, t, frame), field_of_view=0.5, min_range=0.2,
            max_range=5.0, range=r)))
    for t in ODOM_TIMES:
        quaternion = _make(ts, "geometry_msgs/msg/Quaternion", z=math.sin(0.25), w=math.cos(0.25))
        pose = _make(ts, "geometry_msgs/msg/Pose", position=_make(ts, "geometry_msgs/msg/Point", x=t),
                     orientation=quaternion)
        odom = _make(ts, "nav_msgs/msg/Odometry", header=_header(ts, t, "odom"), child_frame_id="base",
                     pose=_make(ts, "geometry_msgs/msg/PoseWithCovariance", pose=pose, covariance=np.zeros(36)),
                     twist=_make(ts, "geometry_msgs/msg/TwistWithCovariance", covariance=np.zeros(36),
                                 twist=_make(ts, "geometry_msgs/msg/Twist",
                                             linear=_make(ts, "geometry_msgs/msg/Vector3"),
                                             angular=_make(ts, "geometry_msgs/msg/Vector3"))))
        out.append((t, "/odom", "nav_msgs/msg/Odometry", odom))
        out.append((t, "/tf", "tf2_msgs/msg/TFMessage", _tf(ts, t, quaternion)))
    return sorted(out, key=lambda m: m[0])


#: a point cloud at 1.05 s: x, y, z as float32, 16 bytes a point, its row padded by 4 bytes
CLOUD = [(1.0, 0.0, 0.0), (0.0, 2.0, 0.1), (math.nan, math.nan, math.nan), (0.0, 1.5, -0.2)]


def _cloud(ts, t):
    rows = np.zeros((len(CLOUD), 4), dtype="<f4")
    rows[:, :3] = CLOUD
    data = np.concatenate([rows.view(np.uint8).ravel(), np.zeros(4, np.uint8)])
    fields = [_make(ts, "sensor_msgs/msg/PointField", name=k, offset=4 * i, datatype=7, count=1)
              for i, k in enumerate("xyz")]
    return _make(ts, "sensor_msgs/msg/PointCloud2", header=_header(ts, t, "lidar"), height=1, width=len(CLOUD),
                 fields=fields, is_bigendian=False, point_step=16, row_step=16 * len(CLOUD) + 4, data=data,
                 is_dense=False)


def _tf(ts, t, quaternion):
    def transform(child, x):
        return _make(ts, "geometry_msgs/msg/TransformStamped", header=_header(ts, t, "odom"),
                     child_frame_id=child, transform=_make(
                         ts, "geometry_msgs/msg/Transform", rotation=quaternion,
                         translation=_make(ts, "geometry_msgs/msg/Vector3", x=x)))

    def mount(child):   # the laser at the robot's centre, facing forward, as a state publisher says it on /tf
        return _make(ts, "geometry_msgs/msg/TransformStamped", header=_header(ts, t, "base_link"),
                     child_frame_id=child, transform=_make(
                         ts, "geometry_msgs/msg/Transform", rotation=_make(ts, "geometry_msgs/msg/Quaternion", w=1.0),
                         translation=_make(ts, "geometry_msgs/msg/Vector3")))

    return _make(ts, "tf2_msgs/msg/TFMessage", transforms=[mount("laser"), transform("base_link", t + 10)])


def write_sonar_topics(path):
    """A ROS 1 bag of two sonars, each on its own topic with an empty frame: /front and /back."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC)
    readings = [(1.0, "/front", 1.0), (1.1, "/back", 2.0), (1.2, "/front", 3.0), (1.3, "/back", 4.0)]
    with Writer(path) as writer:
        connections = {t: writer.add_connection(t, "sensor_msgs/msg/Range", typestore=ts) for t in ("/front", "/back")}
        for t, topic, r in readings:
            msg = _make(ts, "sensor_msgs/msg/Range", header=_header(ts, t, ""), min_range=0.2, max_range=5.0,
                        range=r)
            writer.write(connections[topic], int(t * 1e9), ts.serialize_ros1(msg, "sensor_msgs/msg/Range"))
    return path


def store(kind: str):
    """rosbags' message types for a ``ros1`` bag (with tf2_msgs) or a ROS 2 one."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    if kind != "ros1":
        return get_typestore(Stores.ROS2_HUMBLE)
    ts = get_typestore(Stores.ROS1_NOETIC)
    # ROS 1's own store lacks tf2_msgs: its one message, from its definition
    ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    return ts


def write_bag(folder, kind: str, compression: str = "none"):
    """Write the test bag of ``kind`` ("ros1", "sqlite3", "mcap") under ``folder``; its path.

    A ROS 2 bag may be stored compressed with zstd (``compression``: "message", "file", or "storage" for an
    MCAP's chunks); its path is then the bag's folder.
    """
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    ts = store(kind)
    if kind == "ros1":
        path = folder / "run.bag"
        writer, serialize = Writer1(path), ts.serialize_ros1
    else:
        root = folder / f"run-{kind}"
        shutil.rmtree(root, ignore_errors=True)
        plugin = StoragePlugin.SQLITE3 if kind == "sqlite3" else StoragePlugin.MCAP
        writer, serialize = Writer2(root, version=9, storage_plugin=plugin), ts.serialize_cdr
        path = root / f"run-{kind}.{'db3' if kind == 'sqlite3' else 'mcap'}"
        if compression != "none":
            writer.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
            path = root
    with writer:
        connections = {}
        for t, topic, msgtype, msg in _messages(ts):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=ts)
            writer.write(connections[topic], int(round(t * 1e9)) + 1000, serialize(msg, msgtype))
    return path
