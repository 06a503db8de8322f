"""std_msgs/String as DDS carries it (ros/string_wire.py): the server's pre-encoded publications
and raw reads are exactly rclpy's serialized messages."""

from __future__ import annotations

import pytest
from rclpy.serialization import deserialize_message, serialize_message
from std_msgs.msg import String

from dsr_graph.ros.string_wire import cdr_utf8, string_cdr

pytestmark = pytest.mark.unit

TEXTS = ["", "a", '{"seq":1,"ops":[]}', "héllo, cámara: ü€𝄞", "x" * 4097]


@pytest.mark.parametrize("text", TEXTS, ids=range(len(TEXTS)))
def test_a_text_encodes_as_rclpy_serializes_it_and_reads_back(text):
    wire = string_cdr(text)
    assert wire == serialize_message(String(data=text))
    assert deserialize_message(wire, String).data == text
    assert cdr_utf8(wire).decode() == text


def test_what_is_not_a_serialized_string_is_refused_by_name():
    for bad in (b"", b"\x00\x01\x00\x00", b"\x00\x01\x00\x00\x09\x00\x00\x00ab\x00"):
        with pytest.raises(ValueError, match="std_msgs/String"):
            cdr_utf8(bad)
    no_nul = b"\x00\x01\x00\x00\x02\x00\x00\x00ab"
    with pytest.raises(ValueError, match="wrong length"):
        cdr_utf8(no_nul)
    big_endian = b"\x00\x00\x00\x00\x00\x00\x00\x02a\x00"
    assert cdr_utf8(big_endian) == b"a"
