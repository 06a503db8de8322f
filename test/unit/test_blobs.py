"""Large binary values beside the JSON (protocol/blobs.py): a request's or a delta's values of
16 KiB and more become references by digest, their bytes carried apart; the server takes a
request only with every byte it references (a missing or malformed reference is refused, by
name), a replica without the bytes holds a BlobRef; bytes that do not hash to their digest are
nobody's; CORTEX's byte vectors load into, and are written from, the binary types."""

import json

import numpy as np
import pytest

from dsr_graph.exceptions import MissingBlob, ValueTypeError
from dsr_graph.formats.cortex import from_cortex, to_cortex
from dsr_graph.model.binary import BlobRef, array_coercer, dumps, short_text
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol.blobs import (
    INLINE_MAX,
    BlobCache,
    digest_of,
    extract,
    held_refs_in_text,
    refs_in_text,
    resolve,
    sensor_refs_in_text,
)
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, ServerCore

RGB = np.random.default_rng(3).integers(0, 256, (480, 640, 3), dtype=np.uint8)
DEPTH = np.full((480, 640), 1.25, dtype=np.float32)


def camera_core() -> ServerCore:
    core = ServerCore(Graph(Vocabulary.default()))
    insert = {"op": "insert_node", "name": "kinect", "type": "rgbd"}
    assert not isinstance(core.submit(dumps({"ops": [insert]})), Rejection)
    return core


def frame(rgb=RGB, depth=DEPTH, **more) -> dict:
    attrs = {"cam_rgb": rgb, "cam_depth": depth, **more}
    return {"agent": "/camera", "ops": [{"op": "set_node_attrs", "node": "kinect", "attrs": attrs}]}


def test_large_values_become_references_and_small_ones_stay_inline():
    doc, blobs = extract(frame(cam_rgb_width=640))
    attrs = doc["ops"][0]["attrs"]
    assert attrs["cam_rgb"] == {
        "$blob": digest_of(RGB.tobytes()),
        "dtype": "uint8",
        "size": RGB.nbytes,
        "shape": [480, 640, 3],
    }
    assert attrs["cam_rgb_width"] == 640 and set(blobs) == {
        attrs["cam_rgb"]["$blob"],
        attrs["cam_depth"]["$blob"],
    }
    text = dumps(doc)
    assert len(text) < 1000  # the JSON names the bytes, it does not carry them
    assert refs_in_text(text) == set(blobs)
    small = np.zeros(INLINE_MAX // 2, dtype=np.uint8)
    doc, blobs = extract(frame(rgb=small))
    assert isinstance(doc["ops"][0]["attrs"]["cam_rgb"], np.ndarray) and len(blobs) == 1
    assert extract({"ops": [{"op": "delete_node", "node": "x"}]})[1] == {}


def test_the_server_takes_a_request_with_its_bytes_and_the_delta_goes_out_as_references():
    core = camera_core()
    doc, blobs = extract(frame())
    cache = BlobCache()
    for digest, data in blobs.items():
        assert cache.put(digest, data)
    delta = core.submit(dumps(doc), sender="/camera", blobs=cache.get)
    assert not isinstance(delta, Rejection), delta
    stored = core.graph.node("kinect").attrs
    assert np.array_equal(stored["cam_rgb"], RGB) and stored["cam_depth"].dtype == np.float32
    assert delta.get("volatile")  # camera images are sensor data: never journalled
    out, sent = extract(delta, known=cache.digest_of_kept)
    assert set(sent) == set(blobs)  # the same bytes, not hashed again
    replica = Replica(Vocabulary.default())
    replica.load_snapshot(json.loads(dumps(camera_core().snapshot())))
    replica.receive(resolve(json.loads(dumps(out)), cache.get, lazy=True))
    assert np.array_equal(replica.graph.node("kinect").attrs["cam_rgb"], RGB)


def durable_binary_core() -> ServerCore:
    """A server whose vocabulary also has a binary value that is not sensor data (journalled:
    its bytes must come to the server)."""
    doc = Vocabulary.default().to_json()
    doc["attributes"]["photo"] = {"type": "uint8_array", "doc": "a picture kept"}
    core = ServerCore(Graph(Vocabulary.from_json(doc)))
    insert = {"op": "insert_node", "name": "kinect", "type": "rgbd"}
    assert not isinstance(core.submit(dumps({"ops": [insert]})), Rejection)
    return core


def test_a_request_whose_bytes_never_came_is_refused_naming_the_digest_and_changes_nothing():
    core = durable_binary_core()
    doc, blobs = extract(frame(photo=RGB))
    before = core.snapshot()
    rejection = core.submit(dumps(doc), sender="/camera", blobs=lambda d: None)
    assert isinstance(rejection, Rejection) and rejection.violation.rule == "blob-missing"
    assert next(iter(blobs))[:20] in str(rejection.violation) or any(
        d in rejection.violation.element for d in blobs
    )
    assert core.snapshot() == before


def sensor_frame(**more):
    """A camera frame as an agent sends it: sensor data's references name their writer."""
    volatile = Vocabulary.default().volatile
    return extract(frame(**more), sensor_at=lambda a: "camera" if a in volatile else None)


def test_sensor_data_is_taken_by_its_digest_and_its_bytes_never_reach_the_server():
    """One hop: a camera frame's references name the writer ("at"), the server keeps them as
    BlobRefs (digest, type, shape, writer) and sends them on as they came, never the bytes; a
    replica that was sent the bytes by the writer holds the image."""
    core = camera_core()
    doc, blobs = sensor_frame()
    text = dumps(doc)
    assert sensor_refs_in_text(text) == set(blobs) == refs_in_text(text)
    assert not held_refs_in_text(text)
    delta = core.submit(text, sender="/camera", blobs=lambda d: None)
    assert not isinstance(delta, Rejection), delta
    stored = core.graph.node("kinect").attrs["cam_rgb"]
    assert isinstance(stored, BlobRef) and stored.at == "camera" and stored.shape == (480, 640, 3)
    out, sent = extract(delta)
    out = json.loads(dumps(out))  # as it goes on dsr/deltas
    assert sent == {} and out["ops"][0]["attrs"]["cam_rgb"]["at"] == "camera"
    assert sensor_refs_in_text(dumps(out)) == set(blobs)
    cache = BlobCache()  # the replica's, filled from dsr/sensor_blobs/camera
    for digest, data in blobs.items():
        cache.put(digest, data)
    replica = Replica(Vocabulary.default())
    replica.load_snapshot(json.loads(dumps(camera_core().snapshot())))
    replica.receive(resolve(out, cache.get, lazy=True))
    assert np.array_equal(replica.graph.node("kinect").attrs["cam_rgb"], RGB)
    # the writer is the request's sender, whatever the request claims
    claimed, _ = extract(frame(), sensor_at=lambda a: "someone_else")
    assert not isinstance(core.submit(dumps(claimed), sender="/camera"), Rejection)
    assert core.graph.node("kinect").attrs["cam_depth"].at == "camera"
    # a late joiner's snapshot and a restarted server: the reference, with its writer
    restored = ServerCore.from_snapshot(json.loads(dumps(core.snapshot())), Vocabulary.default())
    kept = restored.graph.node("kinect").attrs["cam_depth"]
    assert isinstance(kept, BlobRef) and kept.at == "camera" and kept.dtype == "float32"


def test_a_durable_binary_value_still_needs_its_bytes_whatever_its_reference_says():
    """Only a sensor attribute's value may be kept by reference: an "at" on a durable value's
    reference does not spare it its bytes (they are journalled)."""
    core = durable_binary_core()
    doc, blobs = extract(frame(photo=RGB), sensor_at=lambda a: "camera")
    rejection = core.submit(dumps(doc), sender="/camera", blobs=lambda d: None)
    assert isinstance(rejection, Rejection) and rejection.violation.rule == "blob-missing"


@pytest.mark.parametrize(
    "ref, error",
    [
        ({"$blob": "md5:abc", "dtype": "uint8", "size": 3, "shape": [3]}, "sha256:"),
        ({"$blob": "sha256:" + "0" * 64, "dtype": "int64", "size": 8, "shape": [1]}, "dtype"),
        ({"$blob": "sha256:" + "0" * 64, "dtype": "uint8", "size": 5, "shape": [3]}, "not 5"),
        ({"$blob": "sha256:" + "0" * 64, "dtype": "uint8", "size": -1, "shape": [3]}, "size"),
        ({"$blob": "sha256:" + "0" * 64, "dtype": "uint8", "size": 3, "shape": [3], "x": 1}, "x"),
        (
            {"at": "a/b", "$blob": "sha256:" + "0" * 64, "dtype": "uint8", "size": 3, "shape": [3]},
            '"at"',
        ),
    ],
)
def test_a_malformed_reference_is_refused_by_name(ref, error):
    core = camera_core()
    doc = {"ops": [{"op": "set_node_attrs", "node": "kinect", "attrs": {"cam_rgb": ref}}]}
    rejection = core.submit(json.dumps(doc), sender="/camera", blobs=lambda d: b"\0\0\0")
    assert isinstance(rejection, Rejection) and rejection.violation.rule == "malformed"
    assert error in rejection.violation.message


def test_bytes_of_another_length_than_the_reference_are_refused():
    core = camera_core()
    doc, blobs = extract(frame())
    rejection = core.submit(dumps(doc), sender="/camera", blobs=lambda d: b"short")
    assert isinstance(rejection, Rejection) and "not" in rejection.violation.message


def test_bytes_that_do_not_hash_to_their_digest_are_not_kept():
    cache = BlobCache()
    data = RGB.tobytes()
    assert not cache.put(digest_of(b"something else"), data)
    assert not cache.put("sha256:nothex", data)
    assert cache.put(digest_of(data), data) and digest_of(data) in cache


def test_the_cache_keeps_the_newest_within_its_bytes():
    cache = BlobCache(max_bytes=3 * 1000)
    blobs = [bytes([k]) * 1000 for k in range(5)]
    for data in blobs:
        cache.put(digest_of(data), data)
    assert [digest_of(b) in cache for b in blobs] == [False, False, True, True, True]
    assert cache.bytes == 3000 and cache.digest_of_kept(blobs[4]) == digest_of(blobs[4])
    assert cache.digest_of_kept(bytes(blobs[4])) is None or bytes(blobs[4]) is blobs[4]


def test_a_replica_without_the_bytes_holds_a_reference_it_can_name():
    doc, _ = extract(frame())
    resolved = resolve(doc, lambda d: None, lazy=True)
    ref = resolved["ops"][0]["attrs"]["cam_rgb"]
    assert isinstance(ref, BlobRef) and ref.shape == (480, 640, 3) and ref.size == RGB.nbytes
    assert short_text(ref) == "<uint8 480x640x3, not fetched>"
    with pytest.raises(MissingBlob, match="did not come"):
        resolve(doc, lambda d: None)
    replica = Replica(Vocabulary.default())
    replica.load_snapshot(json.loads(dumps(camera_core().snapshot())))
    delta = {"seq": 2, "id": "x", "agent": "/camera", **resolved}
    replica.receive(delta)
    assert replica.graph.node("kinect").attrs["cam_rgb"] == ref
    with pytest.raises(ValueTypeError, match="uint16"):
        array_coercer("uint16_array")(ref)  # a reference is only good for its own type


def test_cortex_byte_vectors_load_as_binary_values_and_are_written_back():
    cortex = {
        "DSRModel": {
            "symbols": {
                "1": {
                    "id": 1,
                    "name": "camera",
                    "type": "rgbd",
                    "attribute": {
                        "cam_rgb": {"type": 5, "value": [1, 2, 3, 4, 5, 6]},
                        "cam_depth": {"type": 5, "value": []},
                    },
                    "links": [],
                }
            }
        }
    }
    graph, violations = from_cortex(cortex)
    assert violations == []
    attrs = graph.node("camera").attrs
    assert attrs["cam_rgb"].tolist() == [1, 2, 3, 4, 5, 6] and attrs["cam_depth"].size == 0
    back = to_cortex(graph)["DSRModel"]["symbols"]["1"]["attribute"]
    assert back["cam_rgb"] == {"type": 5, "value": [1, 2, 3, 4, 5, 6]}
    with pytest.raises(ValueTypeError, match="bytes"):
        array_coercer("uint8_array")([1, 300])
    with pytest.raises(ValueTypeError, match="whole number"):
        array_coercer("float32_array")([1, 2, 3])


def test_a_snapshot_carries_large_values_by_reference_and_a_joiner_resolves_them():
    core = camera_core()
    doc, blobs = extract(frame())
    cache = BlobCache()
    for digest, data in blobs.items():
        cache.put(digest, data)
    assert not isinstance(core.submit(dumps(doc), sender="/camera", blobs=cache.get), Rejection)
    snapshot, sent = extract(core.snapshot(), known=cache.digest_of_kept)
    assert set(sent) == set(blobs) and len(dumps(snapshot)) < 10_000
    joiner = Replica(Vocabulary.default())
    joiner.load_snapshot(resolve(json.loads(dumps(snapshot)), cache.get, lazy=True))
    assert np.array_equal(joiner.graph.node("kinect").attrs["cam_depth"], DEPTH)
    late = Replica(Vocabulary.default())  # without the bytes: references it can name
    late.load_snapshot(resolve(json.loads(dumps(snapshot)), lambda d: None, lazy=True))
    assert isinstance(late.graph.node("kinect").attrs["cam_rgb"], BlobRef)


def test_a_value_made_from_a_blob_goes_out_as_the_same_bytes_not_hashed_again():
    import array

    data = array.array("B", RGB.tobytes())  # as a received message holds them
    cache = BlobCache()
    assert cache.put(digest_of(data), data)
    doc, _ = extract(frame())
    value = resolve(doc, cache.get, lazy=True)["ops"][0]["attrs"]["cam_rgb"]
    assert not value.flags.writeable and np.array_equal(value, RGB)
    hashed = []
    _, blobs = extract(
        frame(rgb=value), known=lambda b: hashed.append(b) or cache.digest_of_kept(b)
    )
    assert blobs[digest_of(data)] is data  # the very bytes it came in, not a copy


def test_the_viewer_s_past_holds_an_image_by_reference_its_present_whole():
    from dsr_graph.protocol.history import History

    core = camera_core()
    history = History(Vocabulary.default())
    history.reset(json.loads(dumps(core.snapshot())))
    delta = core.submit(dumps(frame()), sender="/camera")  # volatile: no seq of its own
    history.add(json.loads(dumps(delta)))
    mark = {"op": "set_node_attrs", "node": "kinect", "attrs": {"color": "red"}}
    history.add(json.loads(dumps(core.submit(dumps({"ops": [mark]}), sender="/x"))))
    history.reset(json.loads(dumps(core.snapshot())))  # a checkpoint holding the image
    assert np.array_equal(history.graph.node("kinect").attrs["cam_rgb"], RGB)
    assert max(len(t) for t in history._snapshots.values()) < 10_000
    past = history.graph_at(history.seq)
    assert np.array_equal(past.node("kinect").attrs["cam_rgb"], RGB)  # now: the live graph
    history.add(json.loads(dumps(core.submit(dumps({"ops": [mark]}), sender="/x"))))
    before = history.graph_at(history.seq - 1).node("kinect").attrs["cam_rgb"]
    assert isinstance(before, BlobRef) and before.shape == (480, 640, 3)


def test_the_viewer_asks_the_server_for_bytes_it_missed_and_serves_only_that_seq_s():
    import asyncio

    from aiohttp.test_utils import TestClient, TestServer

    from dsr_graph.protocol.history import History
    from dsr_graph.web.events import Broadcaster
    from dsr_graph.web.viewer_app import make_app

    core = camera_core()
    core.submit(dumps(frame()), sender="/camera")
    snapshot, _ = extract(core.snapshot())
    history = History(Vocabulary.default())  # joined after the frame's bytes went by
    history.reset(resolve(json.loads(dumps(snapshot)), lambda d: None, lazy=True))
    ref = history.graph.node("kinect").attrs["cam_rgb"]
    assert isinstance(ref, BlobRef)
    server = {"cam_rgb": RGB.tobytes()}  # what dsr/get_blob answers now
    asked = []

    async def fetch_blob(node, attribute, digest, at):
        asked.append((node, attribute, at))
        if server.get(attribute) is None:
            raise TimeoutError
        data = server[attribute]
        return data if digest_of(data) == digest else None

    async def main(fetch):
        app = make_app(history, Broadcaster(), fetch_blob=fetch)
        async with TestClient(TestServer(app)) as client:
            r = await client.get("/api/image?node=kinect&attr=cam_rgb")
            body = await r.read()
            return r.status, body, r.headers, body.decode(errors="replace")

    status, body, headers, _ = asyncio.run(main(fetch_blob))
    # the server's test frame came with its bytes (no writer named): the server is asked
    assert status == 200 and body == RGB.tobytes() and asked == [("kinect", "cam_rgb", None)]
    assert headers["X-DSR-Dtype"] == "uint8" and headers["X-DSR-Shape"] == "480,640,3"
    server["cam_rgb"] = bytes(RGB.nbytes)  # a newer frame: not this seq's image
    status, _, _, text = asyncio.run(main(fetch_blob))
    assert status == 404 and "no longer holds" in text
    server["cam_rgb"] = None
    status, _, _, text = asyncio.run(main(fetch_blob))
    assert status == 503 and "did not answer" in text
    status, _, _, text = asyncio.run(main(None))  # a replay: nobody to ask
    assert status == 404 and "not reached the viewer" in text
