"""The rospy shell of the live node: parameters, subscriptions, publications, services, diagnostics, shutdown.

rospy and ROS 1's message packages are an optional dependency of
``novelty``: they are imported here, at the top of this module, and this
module only by ``novelty node`` when it runs (``apt-get install
python3-rospy ...`` and a virtual environment made with
``--system-site-packages``: ``docs/guide/live-robot.md``).

Everything between the bytes a subscription delivers and the novelty
published is :class:`~novelty.rosnode.scoring.LiveScorer`'s, the same
reading and detector as ``novelty run`` on a bag; this module only moves
messages in and out:

- **in**: every followed topic (the scans', ``/tf``, ``/tf_static``, a pose
  topic) is subscribed as ``rospy.AnyMsg``, so that its bytes reach the bag
  reader's own decoders; callbacks only queue them. A worker thread scores
  them in arrival order; when more than ``~queue_size`` scans wait, the oldest
  is dropped and counted (transforms are never dropped);
- **out**, per scan, stamped with the scan's own header stamp: ``~novelty``
  (``std_msgs/Float32``, what ``rqt_plot`` draws), ``~novelty_stamped``
  (``geometry_msgs/Vector3Stamped``: x the novelty, y the alarm 1/0, z the
  threshold), ``~alarm`` (``std_msgs/Bool``, latched) and, for a map while
  someone listens, ``~novel_cells`` (``visualization_msgs/MarkerArray``: the
  cells above the threshold, in the fixed frame, coloured by novelty);
  ``/diagnostics`` (``diagnostic_msgs/DiagnosticArray``) once a second of the
  wall clock;
- **services** (``std_srvs``): ``~set_learning`` (``SetBool``: false freezes),
  ``~save`` (``Trigger``: the model to ``~save``, atomically) and ``~reset``
  (``Trigger``: back to the model at start);
- **shutdown** (SIGINT, SIGTERM, ``rosnode kill``): the scan under way is
  finished, then the model saved to ``~save`` if given;
- **the master**: checked once a second; while it is away the node goes on
  over the connections it has; when one is back, the node registers its
  topics and services with it again.

Shares its name with novelty/cli/node.py, the command that starts it (a command's module is named
after the command).
"""

from __future__ import annotations

import collections
import struct
import sys
import threading
import time

import genpy
import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Point, Vector3, Vector3Stamped
from std_msgs.msg import Bool, ColorRGBA, Float32, Header
from std_srvs.srv import SetBool, SetBoolResponse, Trigger, TriggerResponse
from visualization_msgs.msg import Marker, MarkerArray

from .._version import __version__
from ..io.ros.decoders import DECODED
from .scoring import LiveScorer, Scored, model_size
from .setup import StartError, build, warm_up

__all__ = ["Node", "main"]

#: How long the worker waits for a message before it lets held scans go whose wait is over (s).
TICK = 0.02
_HEADER = struct.Struct("<3I")


def main(argv: list[str]) -> int:
    """Start the node with ``argv`` (ROS arguments: ``_param:=value``, ``from:=to``, ``__name:=``); its exit code."""
    uri = rosgraph.get_master_uri()
    if not rosgraph.Master("/novelty").is_online():
        raise StartError(f"no ROS master at {uri}: start roscore (or set ROS_MASTER_URI).")
    rospy.init_node("novelty", argv=["novelty node"] + list(argv))
    try:
        scorer, settings, topics = build(rospy.get_param("~", {}), rospy.resolve_name,
                                         where=rospy.get_name())
    except StartError:
        rospy.signal_shutdown("the node could not start")
        raise
    if settings.unused:
        rospy.loginfo(f"novelty: ~model {settings.model} is loaded; {' and '.join(settings.unused)} not used.")
    rospy.loginfo("novelty: compiling the detector's kernels before subscribing (on a first run, up to a minute)")
    warm_up(scorer, settings)
    node = Node(scorer, settings, topics)
    rospy.on_shutdown(node.close)
    node.start()
    rospy.loginfo(node.describe())
    rospy.spin()
    return 0


class Node:
    """The node's topics, services and threads around a :class:`LiveScorer`."""

    def __init__(self, scorer: LiveScorer, settings, topics: list[str]):
        self.scorer, self.settings, self.topics = scorer, settings, topics
        self.lock = threading.Lock()             # the scorer: the worker, the services, the diagnostics
        self.outputs = threading.Lock()          # the publishers, while a master back has them made again
        self.queue: collections.deque = collections.deque()
        self.ready = threading.Condition()
        self.scans_waiting = 0
        self.stopping = threading.Event()
        self.headers: collections.OrderedDict = collections.OrderedDict()   # a scan's time -> its exact stamp
        self.master_pid = None
        self.closed = False
        self.simulated = bool(rospy.get_param("/use_sim_time", False))

    # -------------------------------------------------------------- set up
    def start(self) -> None:
        self._register()
        self.master_pid = self._master_pid()
        self.worker = threading.Thread(target=self._work, name="novelty scoring", daemon=True)
        self.watch = threading.Thread(target=self._watch, name="novelty diagnostics", daemon=True)
        self.worker.start()
        self.watch.start()

    def _register(self) -> None:
        """Subscriptions, publications and services, with the master there is now."""
        self.subscribers = [rospy.Subscriber(topic, rospy.AnyMsg, self._arrive, callback_args=topic,
                                             queue_size=None, tcp_nodelay=True) for topic in self.topics]
        self.pub_novelty = rospy.Publisher("~novelty", Float32, queue_size=100)
        self.pub_stamped = rospy.Publisher("~novelty_stamped", Vector3Stamped, queue_size=100)
        self.pub_alarm = rospy.Publisher("~alarm", Bool, queue_size=100, latch=True)
        self.pub_cells = rospy.Publisher("~novel_cells", MarkerArray, queue_size=100)
        self.pub_diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        self.services = [rospy.Service("~set_learning", SetBool, self._set_learning),
                         rospy.Service("~save", Trigger, self._save),
                         rospy.Service("~reset", Trigger, self._reset)]

    def _unregister(self) -> None:
        for handle in self.subscribers + [self.pub_novelty, self.pub_stamped, self.pub_alarm, self.pub_cells,
                                          self.pub_diagnostics]:
            handle.unregister()
        for service in self.services:
            service.shutdown("registering again")

    def describe(self) -> str:
        s = self.settings
        what = s.detector or f"the model {s.model}"
        return (f"novelty {__version__}: {what} on {', '.join(self.topics[:len(self.scorer.reading.scan_topics)])}"
                f" ({'learning' if self.scorer.learning else 'frozen'}); "
                f"{'the points input' if self.scorer.reading.points else 'rings'} of "
                f"{self.scorer.reading.sectors or 'one a beam (up to 180)'} sectors")

    # -------------------------------------------------------------- in
    def _arrive(self, msg, topic: str) -> None:
        """A subscription's callback: the message queued with its arrival times, nothing else."""
        item = (topic, msg._connection_header.get("type", ""), msg._buff, rospy.get_rostime(), time.monotonic())
        scan = topic in self.scorer.reading.assemblers
        if scan:
            resumed = self.scorer.stats.scan_arrived(item[-1])
            if resumed:
                rospy.logwarn(f"novelty: {resumed}")
        with self.ready:
            self.queue.append(item)
            if scan:
                self.scans_waiting += 1
                if self.scans_waiting > self.settings.queue_size:
                    self._drop_oldest_scan()
            self.ready.notify()

    def _drop_oldest_scan(self) -> None:
        for i, (topic, *_) in enumerate(self.queue):
            if topic in self.scorer.reading.assemblers:
                del self.queue[i]
                self.scans_waiting -= 1
                self.scorer.stats.dropped += 1
                return

    def _work(self) -> None:
        while not self.stopping.is_set():
            with self.ready:
                if not self.queue:
                    self.ready.wait(TICK)
                item = self.queue.popleft() if self.queue else None
                if item is not None and item[0] in self.scorer.reading.assemblers:
                    self.scans_waiting -= 1
            try:
                self._handle(item)
            except Exception as exc:   # noqa: BLE001 - a bug must not stop the robot's node: said, counted
                self.scorer.stats.faults["internal errors"] += 1
                rospy.logerr(f"novelty: an internal error, the message left out: {type(exc).__name__}: {exc}")

    def _handle(self, item) -> None:
        with self.outputs:
            cells = self.pub_cells.get_num_connections() > 0
        with self.lock:
            if item is None:
                scored = self.scorer.tick(time.monotonic(), cells)
            else:
                topic, msgtype, data, stamp, clock = item
                scored = self._take(topic, msgtype, data, stamp, clock, cells)
            said, self.scorer.said[:] = list(self.scorer.said), []
        for line in said:
            rospy.logwarn(f"novelty: {line}")
        with self.outputs:
            for one in scored:
                self._publish(one)

    def _take(self, topic, msgtype, data, stamp, clock, cells) -> list[Scored]:
        msgtype = _type_name(msgtype)
        if msgtype not in DECODED:
            self.scorer.stats.faults["messages of a type not read"] += 1
            self.scorer.say(("type", topic), f"{topic} carries {msgtype}, not read here; read: {', '.join(DECODED)}.")
            return []
        if topic in self.scorer.reading.assemblers and len(data) >= _HEADER.size:
            _, sec, nsec = _HEADER.unpack_from(data, 0)
            self._remember(sec, nsec) if sec or nsec else self._remember(stamp.secs, stamp.nsecs)
        return self.scorer.take(topic, msgtype, data, stamp.to_sec(), clock, cells)

    def _remember(self, sec: int, nsec: int) -> None:
        self.headers[sec + nsec * 1e-9] = (sec, nsec)
        while len(self.headers) > 4096:
            self.headers.popitem(last=False)

    # -------------------------------------------------------------- out
    def _publish(self, one: Scored) -> None:
        sec, nsec = self.headers.get(one.time) or _split(one.time)
        header = Header(stamp=genpy.Time(sec, nsec), frame_id=one.row.frame)
        threshold = _threshold(self.scorer)
        try:
            self.pub_novelty.publish(Float32(one.novelty))
            self.pub_stamped.publish(Vector3Stamped(header, Vector3(one.novelty, float(bool(one.alarm)),
                                                                    threshold)))
            if one.alarm is not None:
                self.pub_alarm.publish(Bool(one.alarm))
            if one.cells is not None:
                self.pub_cells.publish(self._markers(one, header, threshold))
        except rospy.ROSException:   # shutting down: the topics are closed
            return
        self.scorer.stats.published(time.monotonic() - one.arrival)

    def _markers(self, one: Scored, header, threshold: float) -> MarkerArray:
        centres, novelty = one.cells
        novel = novelty > threshold
        cells = getattr(self.scorer.detector, "clusterer_", None)   # a map's world cells (novelty.maps.cells)
        size = float(getattr(cells, "cell_size", 0.1))
        frame = self.settings.fixed_frame or self.scorer.reading.posing.world()
        marker = Marker(header=Header(stamp=header.stamp, frame_id=frame), ns="novel_cells", id=0,
                        type=Marker.CUBE_LIST, action=Marker.ADD)
        marker.pose.orientation.w = 1.0
        marker.scale = Vector3(size, size, 0.05)
        marker.points = [Point(x, y, 0.0) for x, y in centres[novel]]
        # yellow at the threshold to red at 1: the more novel, the redder
        marker.colors = [ColorRGBA(1.0, float(1.0 - v), 0.0, 0.8) for v in novelty[novel]]
        return MarkerArray([marker])

    # -------------------------------------------------------------- diagnostics and the master
    def _watch(self) -> None:
        while not self.stopping.wait(1.0):
            try:
                self._diagnose()
            except rospy.ROSException:   # shutting down: the topics are closed
                return
            except Exception as exc:   # noqa: BLE001 - the diagnostics must outlive what they report
                self.scorer.stats.faults["internal errors"] += 1
                rospy.logerr(f"novelty: an internal error in the diagnostics: {type(exc).__name__}: {exc}")

    def _diagnose(self) -> None:
        """Once a second: the scans stopped?, the master there?, the diagnostics published."""
        with self.lock:
            line = self.scorer.stats.check_stopped(time.monotonic(), self.settings.stopped_after)
            status = self._status()
        if line:
            rospy.logwarn(f"novelty: {line}")
        self._check_master()
        with self.outputs:
            self.pub_diagnostics.publish(DiagnosticArray(header=Header(stamp=rospy.get_rostime()), status=[status]))

    def _status(self) -> DiagnosticStatus:
        stats, scorer = self.scorer.stats, self.scorer
        level, summary = stats.level()
        values = stats.values() + [
            ("learning", "yes" if scorer.learning else "frozen"),
            ("model size (values learned)", str(model_size(scorer.detector))),
            ("poses", scorer.reading.report.poses or "not decided yet"),
            ("clock", "simulated (/clock)" if self.simulated else "wall"),
        ]
        return DiagnosticStatus(level=level, name=f"novelty: {rospy.get_name()}", message=summary,
                                hardware_id=rospy.get_name(), values=[KeyValue(k, v) for k, v in values])

    def _master_pid(self):
        try:
            return rosgraph.Master(rospy.get_name()).getPid()
        except Exception:   # noqa: BLE001 - any failure to reach it: it is away
            return None

    def _check_master(self) -> None:
        pid = self._master_pid()
        if pid == self.master_pid:
            return
        if pid is None:
            self.scorer.stats.faults["master lost"] += 1
            rospy.logwarn(f"novelty: the ROS master at {rosgraph.get_master_uri()} is away; scoring goes on over "
                          "the connections made.")
        else:
            rospy.logwarn("novelty: a ROS master is back; the node's topics and services are registered again.")
            with self.outputs:
                self._unregister()
                self._register()
        self.master_pid = pid

    # -------------------------------------------------------------- services
    def _set_learning(self, request) -> SetBoolResponse:
        with self.lock:
            self.scorer.set_learning(request.data)
        return SetBoolResponse(True, "learning" if request.data else "frozen: scoring without learning")

    def _save(self, request) -> TriggerResponse:
        if not self.settings.save:
            return TriggerResponse(False, "no ~save path was given")
        with self.lock:
            try:
                self.scorer.save(self.settings.save)
            except (ValueError, OSError) as exc:
                return TriggerResponse(False, f"not saved: {exc}")
        return TriggerResponse(True, f"saved to {self.settings.save}")

    def _reset(self, request) -> TriggerResponse:
        with self.lock:
            self.scorer.reset()
        return TriggerResponse(True, "the model is back to its state at start")

    # -------------------------------------------------------------- shutdown
    def close(self) -> None:
        """Finish the scan under way, stop the threads, save the model to ``~save`` if given."""
        if self.closed:
            return
        self.closed = True
        self.stopping.set()
        with self.ready:
            self.ready.notify_all()
        self.worker.join()
        print(f"novelty node: {self.scorer.stats.summary()}.", file=sys.stderr)
        if self.settings.save:
            with self.lock:
                try:
                    self.scorer.save(self.settings.save)
                    print(f"novelty node: model saved to {self.settings.save}.", file=sys.stderr)
                except (ValueError, OSError) as exc:
                    print(f"novelty node: the model was not saved: {exc}", file=sys.stderr)


def _type_name(name: str) -> str:
    """A ROS 1 type name (``sensor_msgs/LaserScan``) in the readers' form (``sensor_msgs/msg/LaserScan``)."""
    parts = name.split("/")
    return name if len(parts) != 2 else f"{parts[0]}/msg/{parts[1]}"


def _split(t: float) -> tuple[int, int]:
    sec = int(t // 1)
    return sec, min(int(round((t - sec) * 1e9)), 999_999_999)


def _threshold(scorer: LiveScorer) -> float:
    value = getattr(scorer.detector, "threshold_", getattr(scorer.detector, "threshold", float("nan")))
    return float(value) if isinstance(value, (int, float)) else float("nan")
