"""A ROS node for the tests: every message of the topics named, in the order it arrives, into a file.

``python -m tests.rosnode.collect OUT TOPIC...``: each message is written
as it arrives (its topic, type and bytes, framed by their lengths) and the
file flushed, so that a test reads what was published in the order it was
published (``rosbag record`` files its messages by their time, which goes
back with a bag played again under ``/use_sim_time``). :func:`read` reads
the file back into ROS's own message classes.
"""

import struct
import sys
import threading

_LENGTH = struct.Struct("<I")


def main(out: str, topics: list[str]) -> None:
    import rospy

    rospy.init_node("collector", argv=sys.argv)
    fh = open(out, "wb")
    lock = threading.Lock()   # each topic's callbacks run in a thread of their own

    def arrived(msg, topic):
        record = b"".join(_LENGTH.pack(len(part)) + part for part in (
            topic.encode(), msg._connection_header["type"].encode(), msg._buff))
        with lock:
            fh.write(record)
            fh.flush()

    for topic in topics:
        rospy.Subscriber(topic, rospy.AnyMsg, arrived, callback_args=topic, queue_size=None)
    rospy.spin()
    fh.close()


def read(path) -> dict:
    """``{topic: [message, ...]}`` in the order they arrived, each of ROS's own message class."""
    import roslib.message

    data = open(path, "rb").read()
    out, at = {}, 0
    while at < len(data):
        parts = []
        for _ in range(3):
            (n,) = _LENGTH.unpack_from(data, at)
            parts.append(data[at + 4:at + 4 + n])
            at += 4 + n
        if at > len(data):   # the collector stopped while it wrote this one
            break
        topic, kind, raw = parts[0].decode(), parts[1].decode(), parts[2]
        out.setdefault(topic, []).append(roslib.message.get_message_class(kind)().deserialize(raw))
    return out


if __name__ == "__main__":
    main(sys.argv[1], [a for a in sys.argv[2:] if ":=" not in a])
