"""The decoders against rosbags' deserialization of the same bytes (ROS 1 and CDR), and hostile messages."""

import math
import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from novelty.io.ros import caps
from novelty.io.ros.caps import MessageError, TruncatedError, Where
from novelty.io.ros.decoders import decode, peek
from novelty.io.ros.messages import LaserScan, Pose, RangeReading

pytest.importorskip("rosbags", reason="the decoders are checked against rosbags (the ros extra)")

from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

from ...io.bag_files import _header, _make  # noqa: E402

WHERE = Where("run.bag", "/t", 7)
STORES = {}


def store(ros1: bool):
    if ros1 not in STORES:
        ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
        if ros1:   # ROS 1's own store lacks tf2_msgs: its one message, from its definition
            ts.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
        STORES[ros1] = ts
    return STORES[ros1]


def serialize(ts, msg, msgtype, ros1):
    return bytes(ts.serialize_ros1(msg, msgtype) if ros1 else ts.serialize_cdr(msg, msgtype))


def quaternion(ts, q):
    return _make(ts, "geometry_msgs/msg/Quaternion", x=q[0], y=q[1], z=q[2], w=q[3])


def pose(ts, p, q):
    return _make(ts, "geometry_msgs/msg/Pose", position=_make(ts, "geometry_msgs/msg/Point", x=p[0], y=p[1], z=p[2]),
                 orientation=quaternion(ts, q))


def odometry(ts, t, p, q):
    vector = _make(ts, "geometry_msgs/msg/Vector3")
    return _make(ts, "nav_msgs/msg/Odometry", header=_header(ts, t, "odom"), child_frame_id="base_link",
                 pose=_make(ts, "geometry_msgs/msg/PoseWithCovariance", pose=pose(ts, p, q), covariance=np.zeros(36)),
                 twist=_make(ts, "geometry_msgs/msg/TwistWithCovariance", covariance=np.zeros(36),
                             twist=_make(ts, "geometry_msgs/msg/Twist", linear=vector, angular=vector)))


def laser(ts, t, frame, ranges, angle_min=-1.0, increment=0.01, range_max=30.0):
    return _make(ts, "sensor_msgs/msg/LaserScan", header=_header(ts, t, frame), angle_min=angle_min,
                 angle_max=angle_min + increment * (len(ranges) - 1), angle_increment=increment, range_min=0.05,
                 range_max=range_max, ranges=np.asarray(ranges, np.float32), intensities=np.zeros(0, np.float32))


def cloud(ts, points, pad=4, datatype=7, **override):
    """A cloud of 16-byte points, each row padded by ``pad`` bytes; ``override`` states other sizes."""
    point_step = 16
    rows = np.zeros((len(points), point_step // 4), dtype="<f4")
    rows[:, :3] = points
    data = np.concatenate([rows.view(np.uint8).ravel(), np.zeros(pad, np.uint8)])
    fields = [_make(ts, "sensor_msgs/msg/PointField", name=k, offset=4 * i, datatype=datatype, count=1)
              for i, k in enumerate("xyz")]
    values = dict(header=_header(ts, 2.5, "lidar"), height=1, width=len(points), fields=fields, is_bigendian=False,
                  point_step=point_step, row_step=point_step * len(points) + pad, data=data, is_dense=False)
    values.update(override)
    return _make(ts, "sensor_msgs/msg/PointCloud2", **values)


ENCODINGS = pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "cdr"])


@ENCODINGS
@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(width=32, allow_nan=True, allow_infinity=True), min_size=1, max_size=40),
       st.floats(-3.0, 3.0, width=32), st.text("abc_/", max_size=9), st.floats(0, 2e9))
def test_laser_scans_decode_as_rosbags_deserializes_them(ros1, ranges, angle_min, frame, t):
    ts = store(ros1)
    t = round(t, 6)
    data = serialize(ts, laser(ts, t, frame, ranges, angle_min), "sensor_msgs/msg/LaserScan", ros1)
    theirs = ts.deserialize_ros1(data, "sensor_msgs/msg/LaserScan") if ros1 else \
        ts.deserialize_cdr(data, "sensor_msgs/msg/LaserScan")
    ours = decode("sensor_msgs/msg/LaserScan", data, ros1, WHERE, "/t")
    assert isinstance(ours, LaserScan) and ours.frame == theirs.header.frame_id.strip("/")
    np.testing.assert_array_equal(ours.ranges, theirs.ranges.astype(np.float64))
    assert ours.stamp == theirs.header.stamp.sec + theirs.header.stamp.nanosec * 1e-9
    assert (ours.angle_min, ours.angle_increment) == (theirs.angle_min, theirs.angle_increment)
    # the field-by-field path (taken for big-endian CDR, or anything unusual) reads the same
    if not ros1:
        big = _big_endian_laser(theirs)
        slow = decode("sensor_msgs/msg/LaserScan", big, False, WHERE, "/t")
        np.testing.assert_array_equal(slow.ranges, ours.ranges)
        assert (slow.stamp, slow.frame, slow.angle_min) == (ours.stamp, ours.frame, ours.angle_min)


def _big_endian_laser(m) -> bytes:
    """A LaserScan in big-endian CDR, written here field by field (rosbags writes little-endian only)."""
    frame = m.header.frame_id.encode() + b"\0"
    out = b"\x00\x00\x00\x00" + struct.pack(">iI", m.header.stamp.sec, m.header.stamp.nanosec)
    out += struct.pack(">I", len(frame)) + frame
    out += b"\0" * (-(len(out) - 4) % 4)
    out += struct.pack(">7f", m.angle_min, m.angle_max, m.angle_increment, m.time_increment, m.scan_time,
                       m.range_min, m.range_max)
    out += struct.pack(">I", len(m.ranges)) + np.asarray(m.ranges, ">f4").tobytes() + struct.pack(">I", 0)
    return out


@ENCODINGS
def test_poses_ranges_and_transforms_decode_as_rosbags_deserializes_them(ros1):
    ts = store(ros1)
    q = (0.1, -0.2, math.sin(0.4), math.cos(0.4))
    q = tuple(v / math.sqrt(sum(c * c for c in q)) for v in q)
    odom = decode("nav_msgs/msg/Odometry", serialize(ts, odometry(ts, 3.25, (1.5, -2.0, 0.5), q),
                                                     "nav_msgs/msg/Odometry", ros1), ros1, WHERE, "/odom")
    x, y, z, w = q
    assert isinstance(odom, Pose) and (odom.stamp, odom.x, odom.y) == (3.25, 1.5, -2.0)
    assert odom.theta == pytest.approx(math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))
    stamped = _make(ts, "geometry_msgs/msg/PoseStamped", header=_header(ts, 4.0, "map"), pose=pose(ts, (7, 8, 9), q))
    got = decode("geometry_msgs/msg/PoseStamped", serialize(ts, stamped, "geometry_msgs/msg/PoseStamped", ros1),
                 ros1, WHERE, "/p")
    assert (got.x, got.y, got.theta) == (7.0, 8.0, odom.theta)
    sonar = _make(ts, "sensor_msgs/msg/Range", header=_header(ts, 5.5, "/sonar_3"), field_of_view=0.5,
                  min_range=0.2, max_range=5.0, range=1.25)
    reading = decode("sensor_msgs/msg/Range", serialize(ts, sonar, "sensor_msgs/msg/Range", ros1), ros1, WHERE, "/s")
    assert reading == RangeReading(5.5, 1.25, "sonar_3", np.float32(0.2), 5.0, np.float32(0.5), "sonar_3")
    transforms = [_make(ts, "geometry_msgs/msg/TransformStamped", header=_header(ts, 6.0 + k, "odom/"),
                        child_frame_id=f"/base_{k}", transform=_make(
                            ts, "geometry_msgs/msg/Transform", rotation=quaternion(ts, q),
                            translation=_make(ts, "geometry_msgs/msg/Vector3", x=k, y=2.0, z=-1.0))) for k in range(3)]
    tf = _make(ts, "tf2_msgs/msg/TFMessage", transforms=transforms)
    got = decode("tf2_msgs/msg/TFMessage", serialize(ts, tf, "tf2_msgs/msg/TFMessage", ros1), ros1, WHERE, "/tf",
                 static=True)
    assert [(t.stamp, t.parent, t.child, t.translation, t.static) for t in got] == [
        (6.0 + k, "odom", f"base_{k}", (float(k), 2.0, -1.0), True) for k in range(3)]
    assert got[0].rotation == pytest.approx(q)
    # the field-by-field path reads the same transforms
    import novelty.io.ros.decoders as decoders

    fast = decoders._little_endian_transforms
    try:
        decoders._little_endian_transforms = lambda c, static: None
        slow = decode("tf2_msgs/msg/TFMessage", serialize(ts, tf, "tf2_msgs/msg/TFMessage", ros1), ros1, WHERE,
                      "/tf", static=True)
    finally:
        decoders._little_endian_transforms = fast
    assert slow == got


@ENCODINGS
def test_a_point_cloud_with_padded_rows(ros1):
    ts = store(ros1)
    points = [(1.0, 0.0, 0.0), (0.0, 2.0, 0.1), (math.nan, 0.0, 0.0)]
    stamp, frame, xyz = decode("sensor_msgs/msg/PointCloud2", serialize(ts, cloud(ts, points),
                                                                        "sensor_msgs/msg/PointCloud2", ros1),
                               ros1, WHERE, "/c")
    assert (stamp, frame) == (2.5, "lidar")
    np.testing.assert_array_equal(xyz, np.array(points, dtype=np.float32).astype(np.float64))


@ENCODINGS
@pytest.mark.parametrize("override, field, message", [
    (dict(datatype=0), "fields[0].datatype", "is 0 for x; PointField's datatypes are 1-8"),
    (dict(point_step=8), "fields[2].offset", "puts z at byte 8 of a 8-byte point"),
    (dict(row_step=20), "row_step", "is 20: a row of 3 points of 16 bytes needs 48"),
    (dict(height=2), "data", "reaches byte 104 of a message of 52"),
    (dict(width=10**7, row_step=16 * 10**7), "height x width", "states 10,000,000 points; at most 4,000,000"),
])
def test_a_cloud_whose_layout_does_not_hold_is_refused_naming_its_field(ros1, override, field, message):
    ts = store(ros1)
    override = dict(override)   # shared by both encodings
    datatype = override.pop("datatype", 7)
    msg = cloud(ts, [(1.0, 0.0, 0.0), (0.0, 2.0, 0.1), (0.5, 0.5, 0.5)], datatype=datatype, **override)
    with pytest.raises(MessageError) as info:
        decode("sensor_msgs/msg/PointCloud2", serialize(ts, msg, "sensor_msgs/msg/PointCloud2", ros1), ros1, WHERE,
               "/c")
    assert str(info.value).startswith(f"run.bag, topic /t, message 7 ({field}): ")
    assert message in str(info.value)


@ENCODINGS
def test_hostile_scans_get_errors_that_name_their_field(ros1):
    ts = store(ros1)
    empty = serialize(ts, laser(ts, 1.0, "laser", []), "sensor_msgs/msg/LaserScan", ros1)
    with pytest.raises(MessageError, match=r"run.bag, topic /t, message 7 \(ranges\): holds no beams"):
        decode("sensor_msgs/msg/LaserScan", empty, ros1, WHERE, "/t")
    whole = serialize(ts, laser(ts, 1.0, "laser", [1.0] * 10), "sensor_msgs/msg/LaserScan", ros1)
    with pytest.raises(TruncatedError, match=r"\(ranges\): reaches byte"):
        decode("sensor_msgs/msg/LaserScan", whole[:-12], ros1, WHERE, "/t")
    # a count beyond the cap is named before anything is made of it
    at = whole.index(struct.pack("<I", 10) + struct.pack("<f", 1.0))
    huge = whole[:at] + struct.pack("<I", 50_000_000) + whole[at + 4:]
    with pytest.raises(MessageError, match=r"\(ranges\): states 50,000,000 beams; at most 100,000 are read "
                                           r"\(novelty.io.ros.caps.MAX_BEAMS\)"):
        decode("sensor_msgs/msg/LaserScan", huge, ros1, WHERE, "/t")
    with pytest.raises(MessageError, match=r"\(ranges\): states 50,000,000 beams"):
        peek("sensor_msgs/msg/LaserScan", huge[:at + 4], ros1, WHERE)
    peek("sensor_msgs/msg/LaserScan", huge[:at], ros1, WHERE)   # the count not reached: nothing to say yet
    nan = serialize(ts, odometry(ts, 1.0, (math.nan, 0.0, 0.0), (0, 0, 0, 1)), "nav_msgs/msg/Odometry", ros1)
    with pytest.raises(MessageError, match=r"\(pose.pose.position.x\): is nan; a pose must be finite"):
        decode("nav_msgs/msg/Odometry", nan, ros1, WHERE, "/odom")


def test_the_caps_can_be_raised(monkeypatch):
    ts = store(True)
    data = serialize(ts, laser(ts, 1.0, "laser", [1.0] * 10), "sensor_msgs/msg/LaserScan", True)
    monkeypatch.setattr(caps, "MAX_BEAMS", 9)
    with pytest.raises(MessageError, match="states 10 beams; at most 9"):
        decode("sensor_msgs/msg/LaserScan", data, True, WHERE, "/t")
    monkeypatch.setattr(caps, "MAX_BEAMS", 10)
    assert len(decode("sensor_msgs/msg/LaserScan", data, True, WHERE, "/t").ranges) == 10


@ENCODINGS
def test_multi_echo_scans_read_one_echo_a_beam(ros1):
    ts = store(ros1)

    def echoes(rows):
        return [_make(ts, "sensor_msgs/msg/LaserEcho", echoes=np.asarray(r, np.float32)) for r in rows]

    msg = _make(ts, "sensor_msgs/msg/MultiEchoLaserScan", header=_header(ts, 1.0, "laser"), angle_min=-1.0,
                angle_max=1.0, angle_increment=1.0, range_min=0.1, range_max=20.0,
                ranges=echoes([[1.0, 2.0, 3.0], [4.0], []]), intensities=echoes([[5.0, 9.0, 1.0], [2.0], []]))
    data = serialize(ts, msg, "sensor_msgs/msg/MultiEchoLaserScan", ros1)
    read = {echo: decode("sensor_msgs/msg/MultiEchoLaserScan", data, ros1, WHERE, "/m", echo=echo).ranges.tolist()
            for echo in ("first", "last", "strongest")}
    # a beam without an echo carries no information (NaN)
    assert read["first"][:2] == [1.0, 4.0] and read["last"][:2] == [3.0, 4.0] and read["strongest"][:2] == [2.0, 4.0]
    assert all(math.isnan(r[2]) for r in read.values())
