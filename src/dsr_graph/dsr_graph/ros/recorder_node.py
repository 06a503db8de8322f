"""``dsr_recorder`` (also ``dsr record FILE.mcap``): records a session to an MCAP file (ROS 2
profile, CDR) that Foxglove, ``ros2 bag`` and ``dsr view --replay`` open. The file format is in
``dsr_graph/formats/mcap_recording.py``.

What it records: the DSR (its graph when recording starts, then every accepted delta, kept as an
exact replica: a gap is filled from a fresh snapshot, written to the file too), and every other
topic of the ROS graph whose name matches ``include`` and not ``exclude`` (found as they appear,
like ``ros2 bag record --all``): /tf, /tf_static, dsr/markers, the poses, the CLARC device topics.
Each topic is subscribed with its publishers' reliability and durability, so latched values
(/tf_static, markers) and best-effort sensor streams are heard; messages are stored as they
arrived (raw CDR, never decoded). The file is flushed every ``flush_period`` seconds, so a
recorder killed outright loses at most that much; an existing file is never overwritten (the
next free ``<stem>.<n>.mcap`` is taken, so a restarted recorder starts a new file).

ROS Parameters: output (required), duration (0: until stopped), include ('.*'), exclude (''),
discovery_period (0.25 s), flush_period (1.0 s), setup_timeout (20 s).
Subscriptions and clients: those of DsrAgent, and every recorded topic.
"""

from __future__ import annotations

import importlib
import re
import sys
import time
from pathlib import Path
from typing import Any

import mcap
import yaml
from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
from mcap.writer import Writer
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
from rclpy.serialization import serialize_message
from std_msgs.msg import String

from dsr_graph import __version__
from dsr_graph.exceptions import DsrError, TimedOutError
from dsr_graph.formats import dsr_json
from dsr_graph.formats.mcap_recording import (
    DSR_METADATA,
    MESSAGE_ENCODING,
    PROFILE,
    SCHEMA_ENCODING,
    message_definition,
)
from dsr_graph.model.binary import compact
from dsr_graph.protocol import topic_names
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.parameters import declare, declare_setup_timeout, float_param, param
from dsr_graph.ros.qos import qos_matching

SNAPSHOT = "dsr/snapshot"  # the recording's channel of whole graphs (relative, as the others)
STRING = "std_msgs/msg/String"


def free_path(path: Path) -> Path:
    """``path`` if nothing is there, else the first free ``<stem>.<n><suffix>``."""
    n = 0
    candidate = path
    while candidate.exists():
        n += 1
        candidate = path.with_name(f"{path.stem}.{n}{path.suffix}")
    return candidate


def _msg_file(pkg: str, name: str) -> Path:
    try:
        return Path(get_package_share_directory(pkg)) / "msg" / f"{name}.msg"
    except PackageNotFoundError:
        raise FileNotFoundError(f"no package {pkg} in AMENT_PREFIX_PATH") from None


def _message_class(type_name: str):
    pkg, kind, name = type_name.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), name)


def _qos_yaml(publishers) -> str:
    """The publishers' QoS as rosbag2 stores it in a channel's ``offered_qos_profiles``, so
    ``ros2 bag play`` publishes latched topics latched again."""
    forever = {"sec": 2147483647, "nsec": 4294967295}  # rosbag2's "infinite" duration
    return yaml.safe_dump(
        [
            {
                "history": int(p.qos_profile.history),
                "depth": int(p.qos_profile.depth),
                "reliability": int(p.qos_profile.reliability),
                "durability": int(p.qos_profile.durability),
                "deadline": forever,
                "lifespan": forever,
                "liveliness": int(p.qos_profile.liveliness),
                "liveliness_lease_duration": forever,
                "avoid_ros_namespace_conventions": False,
            }
            for p in publishers
        ],
        sort_keys=False,
    )


class Recorder(DsrNode):
    NAME = "dsr_recorder"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(
            node,
            "output",
            "",
            "the MCAP file to write (an existing file is kept: <stem>.<n>.mcap is taken)",
            read_only=True,
            required=True,
        )
        declare(
            node,
            "duration",
            0.0,
            "stop after this many seconds (0: until SIGINT or SIGTERM)",
            read_only=True,
            minimum=0.0,
        )
        declare(node, "include", ".*", "record the topics whose full name this regex finds")
        declare(node, "exclude", "", "but not those this regex finds ('' excludes none)")
        declare(
            node,
            "discovery_period",
            0.25,
            "seconds between looks for new topics",
            read_only=True,
            minimum=0.05,
        )
        declare(
            node,
            "flush_period",
            1.0,
            "seconds between flushes to disk (what a killed recorder can lose)",
            read_only=True,
            minimum=0.05,
        )
        declare_setup_timeout(node, 20.0)

    def __init__(self) -> None:
        super().__init__()
        self.agent = DsrAgent(describe=False)  # reads, never writes
        self.path: Path | None = None
        self._stream = None
        self._writer: Writer | None = None
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}  # topic -> channel id
        self._skipped: set[str] = set()  # topics that cannot be recorded (said once)
        self._recording: dict[str, Any] = {}
        self.counts: dict[str, int] = {}
        self._stop_at: float | None = None

    # ------------------------------------------------------------------ set-up
    def setup(self) -> None:
        for name in ("include", "exclude"):
            try:
                re.compile(param(self, name))
            except re.error as e:
                raise ValueError(f"parameter {name} is not a regular expression: {e}") from None
        wanted = Path(param(self, "output")).expanduser()
        if not wanted.parent.is_dir():
            raise DsrError(f"cannot record to {wanted}: {wanted.parent} is not a directory")
        # The server first: a recorder that cannot record leaves no file behind.
        timeout = float_param(self, "setup_timeout")
        deadline = time.monotonic() + timeout
        self.agent.setup(self, timeout_sec=timeout)
        while not self.agent.synced:
            if time.monotonic() >= deadline:
                raise TimedOutError(f"no snapshot from the DSR server within {timeout} s")
            self.spin_once(0.05)
        self._open(wanted)
        self._on_change([], resynced=True)  # the recording starts with the graph as it is now
        self.agent.add_listener(self._on_change)
        self._discover()
        self.create_timer(float_param(self, "discovery_period"), self._discover)
        self.create_timer(float_param(self, "flush_period"), self._writer.flush)
        duration = float_param(self, "duration")
        if duration > 0:
            self._stop_at = time.monotonic() + duration
        self.get_logger().info(f"recording to {self.path}")

    def _open(self, wanted: Path) -> None:
        self.path = free_path(wanted)
        if self.path != wanted:
            self.get_logger().warning(
                f"{wanted} exists and is kept; this recording will be {self.path.name}"
            )
        self._stream = open(self.path, "xb")  # noqa: SIM115 (closed in close())
        self._writer = Writer(self._stream)
        self._writer.start(PROFILE, f"dsr record {__version__} (mcap-python {mcap.__version__})")
        self.deltas_topic = self.resolve_topic_name(topic_names.DELTAS)
        self.snapshot_topic = self.resolve_topic_name(SNAPSHOT)
        self._writer.add_metadata(
            DSR_METADATA,
            {
                "snapshot": self.snapshot_topic,
                "deltas": self.deltas_topic,
                "recorder": self.get_fully_qualified_name(),
                "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            },
        )
        for topic in (self.snapshot_topic, self.deltas_topic):
            self._channel(topic, STRING, "")

    def run(self) -> int:
        while not self.stop_requested() and (
            self._stop_at is None or time.monotonic() < self._stop_at
        ):
            self.spin_once(0.1)
        return 0

    def close(self) -> None:
        if self._writer is None:
            return
        self._writer.finish()
        self._stream.close()
        self._writer = None
        total = sum(self.counts.values())
        # printed: ROS may be shut down already (SIGINT), and its logger with it
        print(
            f"[dsr_recorder] recorded {total} messages on {len(self.counts)} topics to {self.path}",
            file=sys.stderr,
            flush=True,
        )

    # ------------------------------------------------------------------ writing
    def _channel(self, topic: str, type_name: str, qos: str) -> int:
        if type_name not in self._schemas:
            text = message_definition(type_name, _msg_file)
            self._schemas[type_name] = self._writer.register_schema(
                type_name, SCHEMA_ENCODING, text.encode()
            )
        metadata = {"offered_qos_profiles": qos} if qos else {}
        self._channels[topic] = self._writer.register_channel(
            topic, MESSAGE_ENCODING, self._schemas[type_name], metadata
        )
        return self._channels[topic]

    def _write(self, topic: str, data: bytes, publish_time: int | None = None) -> None:
        if self._writer is None:
            return
        now = self.get_clock().now().nanoseconds
        self.counts[topic] = self.counts.get(topic, 0) + 1
        self._writer.add_message(
            self._channels[topic],
            log_time=now,
            data=data,
            publish_time=now if publish_time is None else publish_time,
            sequence=self.counts[topic],
        )

    def _on_change(self, deltas: list[dict[str, Any]], resynced: bool) -> None:
        if resynced:  # the graph as the replica holds it now (the drained deltas included)
            doc = dsr_json.to_json(self.agent.graph, "snapshot", seq=self.agent.replica.seq)
            doc["claims"] = self.agent.replica.claims.to_json()
            self._write(self.snapshot_topic, serialize_message(String(data=compact(doc))))
            return
        for delta in deltas:
            stamp = delta.get("stamp")
            stamp_ns = int(stamp * 1e9) if isinstance(stamp, (int, float)) else None
            self._write(self.deltas_topic, serialize_message(String(data=compact(delta))), stamp_ns)

    # ------------------------------------------------------------------ discovery
    def _discover(self) -> None:
        include = re.compile(param(self, "include"))
        exclude_text = param(self, "exclude")
        exclude = re.compile(exclude_text) if exclude_text else None
        for topic, types in self.get_topic_names_and_types():
            if topic in self._recording or topic in self._skipped:
                continue
            if topic in (self.deltas_topic, self.snapshot_topic):
                continue  # written from the replica, in seq order and without gaps
            if not include.search(topic) or (exclude and exclude.search(topic)):
                continue
            publishers = self.get_publishers_info_by_topic(topic)
            if not publishers:
                continue  # only subscribers so far: nothing to record yet
            if len(types) != 1:
                self._skip(topic, f"it has several types ({', '.join(types)})")
                continue
            try:
                msg_class = _message_class(types[0])
                self._channel(topic, types[0], _qos_yaml(publishers))
            except (ImportError, AttributeError, ValueError, OSError) as e:
                self._skip(topic, f"its type {types[0]} cannot be loaded: {e}")
                continue
            qos = qos_matching(publishers, depth=1000)
            self._recording[topic] = self.create_subscription(
                msg_class, topic, lambda data, t=topic: self._write(t, data), qos, raw=True
            )
            kind = []
            if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL:
                kind.append("latched")
            if qos.reliability == ReliabilityPolicy.BEST_EFFORT:
                kind.append("best effort")
            extra = f" ({', '.join(kind)})" if kind else ""
            self.get_logger().info(f"recording {topic} [{types[0]}]{extra}")

    def _skip(self, topic: str, why: str) -> None:
        self._skipped.add(topic)
        self.get_logger().warning(f"not recording {topic}: {why}")


main = main_for(Recorder)
