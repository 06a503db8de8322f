"""The recording format's pure parts: the ros2msg schemas we write decode what rclpy serialises
(so any ROS 2 tool reads our files), and a recorder never overwrites a file."""

from pathlib import Path

import pytest
from ament_index_python.packages import get_package_share_directory
from mcap.records import Schema
from mcap_ros2.decoder import DecoderFactory
from rclpy.serialization import serialize_message

from dsr_graph.formats.mcap_recording import message_definition


def msg_file(pkg: str, name: str) -> Path:
    return Path(get_package_share_directory(pkg)) / "msg" / f"{name}.msg"


def decode(type_name: str, message):
    """Decoded as the mcap library decodes a recording: from the schema alone."""
    text = message_definition(type_name, msg_file)
    schema = Schema(id=1, name=type_name, encoding="ros2msg", data=text.encode())
    return DecoderFactory().decoder_for("cdr", schema)(serialize_message(message))


def test_a_marker_array_decodes_with_our_schema():
    from visualization_msgs.msg import Marker, MarkerArray

    marker = Marker(ns="dsr", id=7, text="robot", type=Marker.TEXT_VIEW_FACING)
    marker.header.frame_id = "room"
    marker.pose.position.x = 1.5
    marker.color.a = 1.0
    decoded = decode("visualization_msgs/msg/MarkerArray", MarkerArray(markers=[marker]))
    [got] = decoded.markers
    assert (got.ns, got.id, got.text, got.header.frame_id) == ("dsr", 7, "robot", "room")
    assert got.pose.position.x == 1.5 and got.color.a == 1.0


def test_a_tf_message_decodes_with_our_schema():
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage

    t = TransformStamped(child_frame_id="kinect")
    t.header.frame_id = "robot"
    t.transform.translation.z = 1.2
    t.transform.rotation.w = 1.0
    [got] = decode("tf2_msgs/msg/TFMessage", TFMessage(transforms=[t])).transforms
    assert got.child_frame_id == "kinect" and got.transform.translation.z == 1.2


def test_each_dependency_is_written_once_after_a_separator_line():
    text = message_definition("visualization_msgs/msg/MarkerArray", msg_file)
    headers = [line for line in text.splitlines() if line.startswith("MSG: ")]
    assert len(headers) == len(set(headers))
    assert "MSG: visualization_msgs/Marker" in headers and "MSG: std_msgs/Header" in headers
    assert text.count("=" * 80) == len(headers)


@pytest.mark.parametrize(
    "existing,expected",
    [([], "a.mcap"), (["a.mcap"], "a.1.mcap"), (["a.mcap", "a.1.mcap"], "a.2.mcap")],
)
def test_a_recorder_takes_the_next_free_name(tmp_path, existing, expected):
    from dsr_graph.ros.recorder_node import free_path

    for name in existing:
        (tmp_path / name).write_bytes(b"kept")
    assert free_path(tmp_path / "a.mcap") == tmp_path / expected
