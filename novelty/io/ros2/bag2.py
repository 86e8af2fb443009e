"""ROS 2 bags (SQLite ``.db3``, MCAP ``.mcap``, a bag folder) through ``rosbags``, their compressed parts checked first.

``rosbags`` (pure Python, on the package index: ``pip install
'novelty-habituation[ros]'``) reads a ROS 2 bag's storage; it decompresses
without a limit, so :class:`~novelty.io.ros2.inflation.StoredBag` checks
what opening the bag inflates first, and the messages of the topics read
as they are asked for. A bag written without its message
definitions is read with the latest ROS 2 types. :class:`Bag2` gives its
topics, their counts, and each message's bytes in the bag's order, its
length checked against the cap its reader gives before it is handed on.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Iterator, Sequence

from ..ros.caps import Where
from .inflation import StoredBag

__all__ = ["Bag2", "rosbags", "EXTRA"]

#: how to install the optional package that reads ROS 2 bags
EXTRA = "pip install 'novelty-habituation[ros]' (or pip install rosbags)"


def rosbags():
    """``(AnyReader, Stores, get_typestore)`` of the optional ``rosbags``; an ``ImportError`` saying how to get it."""
    # deferred: rosbags is an optional dependency, imported only to open a bag
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise ImportError(f"Reading ROS bags needs the optional package rosbags: {EXTRA}.") from None
    return AnyReader, Stores, get_typestore


class Bag2:
    """An open ROS 2 bag: its topics' types (:attr:`topics`) and counts; :meth:`messages` reads them.

    ``reader`` is ``rosbags``' (:func:`rosbags`), given by the caller that
    imported it. Whatever ``rosbags`` or SQLite raise for a damaged file
    passes through, for the caller to say in its own words.
    """

    def __init__(self, path, reader=None):
        AnyReader, Stores, get_typestore = reader or rosbags()
        self.path = Path(path)
        # rosbags inflates without a limit: what opening inflates is checked first, the messages of the topics
        # read as they are asked for
        self._stored = StoredBag(self.path)
        self._stored.check_storage()
        self._checked: set[str] = set()   # the topics whose messages were checked
        # ROS 2 bags written without their message definitions are read with the latest ROS 2 types
        self.reader = AnyReader([self.path], default_typestore=get_typestore(Stores.LATEST))
        self.reader.open()
        topics = self.reader.topics
        self.topics = {t: info.msgtype for t, info in sorted(topics.items())}
        self._counts = {t: info.msgcount for t, info in topics.items()}

    def count(self, topic: str) -> int:
        """How many messages ``topic`` holds."""
        return self._counts[topic]

    def close(self) -> None:
        self.reader.close()

    def messages(self, topics: Sequence[str], limits: dict[str, tuple[int, Callable]]) -> Iterator[
            tuple[str, str, int, Where, bytes]]:
        """``(topic, type, record time (ns), where, data)`` of each message of ``topics``, in the bag's order.

        ``limits[topic]`` is ``(cap, explain)``: a message longer than
        ``cap`` bytes has its first bytes explained (``explain(prefix,
        where)`` names the field that asks for too much) and is refused.
        """
        if not self._checked.issuperset(topics):
            self._stored.check_messages(topics)
            self._checked.update(topics)
        numbers = dict.fromkeys(topics, 0)
        connections = [c for c in self.reader.connections if c.topic in topics]
        for connection, time, data in self.reader.messages(connections=connections):
            numbers[connection.topic] += 1
            where = Where(self.path, connection.topic, numbers[connection.topic])
            cap, explain = limits[connection.topic]
            if len(data) > cap:
                explain(bytes(data[:4 * 4096]), where)
                raise where.error("length", f"{len(data):,} bytes; at most {cap:,} are read for its type "
                                  "(novelty.io.ros.caps).")
            yield connection.topic, connection.msgtype, time, where, data
