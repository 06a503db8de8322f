"""MCAP recordings of a DSR session (ROS 2 profile, CDR), written by ``dsr record`` and read back
here without ROS (the ``mcap`` and ``mcap-ros2-support`` libraries do the file format and CDR).

What a recording holds:
- every recorded topic as a channel, exactly as ``ros2 bag record`` stores it: schema encoding
  ``ros2msg`` (the type's message definition with its dependencies), message encoding ``cdr``,
  the publishers' QoS in the channel's ``offered_qos_profiles``, so Foxglove, ``ros2 bag`` and
  the mcap CLI open it;
- the DSR itself on two ``std_msgs/msg/String`` JSON channels, named in the file's ``dsr``
  metadata record: ``snapshot`` (the whole graph in our snapshot format: at the start and again
  after any gap the recorder had to fill from the server) and ``deltas`` (each accepted delta
  after it, in seq order, as the server published it). The graph at any moment of the recording
  is the last snapshot before it plus the deltas after that snapshot.
"""

from __future__ import annotations

import json
import struct
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mcap.exceptions import EndOfFile, McapError
from mcap.records import Channel, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap_ros2.decoder import DecoderFactory

from dsr_graph.exceptions import RecordingError

PROFILE = "ros2"
SCHEMA_ENCODING = "ros2msg"
MESSAGE_ENCODING = "cdr"
DSR_METADATA = "dsr"  # metadata record naming the DSR's channels
_SEPARATOR = "=" * 80


def message_definition(type_name: str, msg_file: Callable[[str, str], Path]) -> str:
    """The ``ros2msg`` schema of ``pkg/msg/Type``: its .msg text, then each type it uses (once,
    depth first) after a line of 80 ``=`` and ``MSG: pkg/Type``, as rosbag2 writes it.
    ``msg_file(pkg, name)`` finds a type's .msg file (in the package's share directory)."""
    from rosidl_adapter.parser import parse_message_string

    pkg, _, name = type_name.split("/")
    parts: list[str] = []
    seen: set[str] = set()

    def visit(pkg: str, name: str, top: bool) -> None:
        text = msg_file(pkg, name).read_text()
        parts.append(text if top else f"{_SEPARATOR}\nMSG: {pkg}/{name}\n{text}")
        for field in parse_message_string(pkg, name, text).fields:
            used = field.type
            if not used.is_primitive_type():
                key = f"{used.pkg_name}/{used.type}"
                if key not in seen:
                    seen.add(key)
                    visit(used.pkg_name, used.type, False)

    visit(pkg, name, True)
    return "\n".join(part.rstrip("\n") for part in parts) + "\n"


@dataclass
class Recorded:
    """One message of a recording: its channel's topic, when it was logged (ns), its value."""

    topic: str
    log_time: int
    message: Any


def _open(path: str | Path):
    try:
        stream = open(path, "rb")  # noqa: SIM115 (closed by the caller's generator)
    except OSError as e:
        raise RecordingError(f"cannot open the recording {path}: {e.strerror}") from None
    return stream


def _records(path: str | Path) -> Iterator[Any]:
    """The file's records in order. A recording whose recorder was killed has no footer: its
    records are read up to where it was cut (the last flush), and nothing is invented."""
    read = 0
    with _open(path) as stream:
        try:
            for record in StreamReader(stream).records:
                read += 1
                yield record
        except EndOfFile:
            if not read:
                raise RecordingError(f"{path} is not an MCAP file (it is empty)") from None
        except (McapError, ValueError, struct.error) as e:
            raise RecordingError(f"{path} is not a readable MCAP file: {e}") from None


def dsr_channels(path: str | Path) -> dict[str, str]:
    """The ``dsr`` metadata record: {"snapshot": topic, "deltas": topic, ...}."""
    for record in _records(path):
        if isinstance(record, Metadata) and record.name == DSR_METADATA:
            return dict(record.metadata)
    raise RecordingError(f"{path} holds no '{DSR_METADATA}' metadata: not written by dsr record")


def messages(path: str | Path, topics: list[str] | None = None) -> Iterator[Recorded]:
    """Decoded messages (of the given topics, or all) in the order they were written, which is
    the order the recorder received them (its log times never go back)."""
    factory = DecoderFactory()
    schemas: dict[int, Schema] = {}
    channels: dict[int, Channel] = {}
    for record in _records(path):
        if isinstance(record, Schema):
            schemas[record.id] = record
        elif isinstance(record, Channel):
            channels[record.id] = record
        elif isinstance(record, Message):
            channel = channels[record.channel_id]
            if topics is not None and channel.topic not in topics:
                continue
            decode = factory.decoder_for(channel.message_encoding, schemas.get(channel.schema_id))
            if decode is None:
                raise RecordingError(
                    f"{path}: {channel.topic} is not ROS 2 CDR ({channel.message_encoding})"
                )
            yield Recorded(channel.topic, record.log_time, decode(record.data))


def dsr_events(path: str | Path) -> Iterator[tuple[str, int, dict[str, Any]]]:
    """The DSR's course in a recording: ("snapshot" | "delta", log time ns, document)."""
    channels = dsr_channels(path)
    kinds = {channels["snapshot"]: "snapshot", channels["deltas"]: "delta"}
    for recorded in messages(path, topics=list(kinds)):
        try:
            doc = json.loads(recorded.message.data)
        except ValueError as e:
            raise RecordingError(
                f"{path}: a message on {recorded.topic} is not JSON: {e}"
            ) from None
        yield kinds[recorded.topic], recorded.log_time, doc
