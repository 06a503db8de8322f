"""Large binary values through a running server (protocol/blobs.py): a camera frame (sensor data)
written by one agent reaches a replica that asks for the bytes as equal arrays, one hop, from the
agent's own dsr/sensor_blobs/<name>, which the server never reads, while the JSON on dsr/deltas
names them by digest (a few hundred bytes, not megabytes of base64); a replica that does not ask
holds a BlobRef naming the writer, whose dsr/get_blob/<name> gives the bytes (the server's says
where they are); a durable binary value's request whose bytes never come, or come forged, is
refused by name and changes nothing."""

import json

import numpy as np
from std_msgs.msg import String

from dsr_graph.model.binary import BlobRef, dumps
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol import topic_names
from dsr_graph.protocol.blobs import digest_of, extract
from dsr_graph.ros.blob_topics import blob_message
from dsr_graph.ros.qos import qos_blobs, qos_stream
from dsr_msgs.msg import Blob
from dsr_msgs.srv import GetBlob

from ros_processes import agent_in_session, agent_on_node, send_and_wait, wait_for

RGB = np.random.default_rng(5).integers(0, 256, (480, 640, 3), dtype=np.uint8)
DEPTH = np.linspace(0.5, 4.0, 480 * 640, dtype=np.float32).reshape(480, 640)


def test_a_camera_frame_crosses_as_bytes_beside_a_small_delta(ros):
    ros.procs.start_server(ros.tmp / "state")
    writer = agent_in_session(ros)
    reader = agent_on_node(ros, "reader", blobs=True)
    plain = agent_on_node(ros, "plain", blobs=False)
    texts = []
    raw = ros.session.node.create_subscription(
        String, topic_names.DELTAS, lambda m: texts.append(m.data), qos_stream()
    )
    resent = []
    server_blobs = ros.session.node.create_subscription(
        Blob, topic_names.BLOBS, lambda m: resent.append(m.digest), qos_blobs()
    )
    wait_for(
        lambda: raw.get_publisher_count() > 0 and server_blobs.get_publisher_count() > 0,
        10,
        "dsr/deltas and dsr/blobs matched",
        ros.session,
    )
    insert = {"op": "insert_node", "name": "kinect", "type": "rgbd"}
    assert send_and_wait(ros, writer, {"ops": [insert]}).accepted
    for k in range(3):  # a few frames, each told apart by its first pixel
        rgb = RGB.copy()
        rgb[0, 0, 0] = k
        attrs = {"cam_rgb": rgb, "cam_depth": DEPTH}
        op = {"op": "set_node_attrs", "node": "kinect", "attrs": attrs}
        assert send_and_wait(ros, writer, {"ops": [op]}).accepted
        wait_for(
            lambda k=k: (
                isinstance(got := reader.graph.node("kinect").attrs.get("cam_rgb"), np.ndarray)
                and got[0, 0, 0] == k
            ),
            10,
            f"frame {k} at the reader",
            ros.session,
        )
    seen = reader.graph.node("kinect").attrs
    assert np.array_equal(seen["cam_rgb"][1:], RGB[1:]) and np.array_equal(seen["cam_depth"], DEPTH)
    mine = writer.graph.node("kinect").attrs["cam_rgb"]  # its own write, whole
    assert isinstance(mine, np.ndarray) and mine[0, 0, 0] == 2
    last = digest_of(mine.tobytes())

    def held_last() -> bool:
        held = plain.graph.node("kinect").attrs.get("cam_rgb")
        return isinstance(held, BlobRef) and held.digest == last

    wait_for(held_last, 10, "the last frame at the plain replica", ros.session)
    held = plain.graph.node("kinect").attrs["cam_rgb"]
    writer_name = ros.session.node.get_name()
    assert isinstance(held, BlobRef) and held.shape == (480, 640, 3) and held.at == writer_name
    # the server never had the bytes: it says who has them, and that one gives them
    from_server = get_blob(ros, topic_names.GET_BLOB)
    assert not from_server.found and f"dsr/get_blob/{writer_name}" in from_server.error
    from_writer = get_blob(ros, f"{topic_names.GET_BLOB}/{writer_name}")
    assert from_writer.found and digest_of(bytes(from_writer.data)) == held.digest
    readers = ros.session.node.get_subscriptions_info_by_topic(
        f"/{topic_names.SENSOR_BLOBS}/{writer_name}"
    )
    assert sorted(r.node_name for r in readers) == ["reader"]  # never the server
    wait_for(lambda: sum("cam_rgb" in t for t in texts) == 3, 10, "3 deltas", ros.session)
    frames = [t for t in texts if "cam_rgb" in t]
    assert len(frames) == 3 and max(len(t) for t in frames) < 4000  # no base64 megabytes
    assert resent == []  # the agent's bytes went out once, on its own topic


def test_a_request_whose_bytes_never_come_or_come_forged_is_refused_by_name(ros):
    # a binary value that is not sensor data (journalled): its bytes must reach the server
    vocabulary = Vocabulary.default().to_json()
    vocabulary["attributes"]["photo"] = {"type": "uint8_array", "doc": "a picture kept"}
    (ros.tmp / "vocabulary.json").write_text(json.dumps(vocabulary))
    ros.procs.start_server(ros.tmp / "state", vocabulary_file=ros.tmp / "vocabulary.json")
    writer = agent_in_session(ros)
    insert = {"op": "insert_node", "name": "kinect", "type": "rgbd"}
    assert send_and_wait(ros, writer, {"ops": [insert]}).accepted
    op = {"op": "set_node_attrs", "node": "kinect", "attrs": {"photo": RGB}}
    doc, blobs = extract({"ops": [op]})
    [digest] = blobs
    # the JSON alone, its bytes never published: held a few seconds, then refused
    sent = json.loads(dumps(doc))
    result = send_raw(ros, writer, sent)
    assert not result.accepted and result.reason["rule"] == "blob-missing"
    assert digest in result.error
    # forged bytes under the digest on the writer's own blob topic: dropped by the server
    forged = ros.session.node.create_publisher(
        Blob, f"{topic_names.BLOBS}/{ros.session.node.get_name()}", qos_blobs()
    )
    wait_for(lambda: forged.get_subscription_count() > 0, 10, "the server's blob subscription")
    other = bytes(len(blobs[digest]))
    assert digest_of(other) != digest
    forged.publish(blob_message(digest, other))
    result = send_raw(ros, writer, sent)
    assert not result.accepted and result.reason["rule"] == "blob-missing"
    assert "photo" not in writer.graph.node("kinect").attrs


def get_blob(ros, service):
    """kinect.cam_rgb asked of ``service`` (a dsr_msgs/GetBlob), bounded."""
    client = ros.session.node.create_client(GetBlob, service)
    wait_for(client.service_is_ready, 10, service, ros.session)
    return ros.session.call(
        client, GetBlob.Request(node="kinect", attribute="cam_rgb"), 10, service
    )


def send_raw(ros, agent, doc):
    """A request as its JSON only: the agent finds no binary value in it to send beside."""
    results = []
    agent.send(doc, results.append)
    wait_for(lambda: results, 15, "a verdict", ros.session)
    return results[0]
