"""Binary values: bytes and typed arrays (uint8, uint16, float32, with a shape) in the model, in
transactions, snapshots, world files and the journal (base64 in JSON), their size limit, and
the clear errors bad ones get."""

import json

import numpy as np
import pytest

from dsr_graph.exceptions import RuleViolation, ValueTypeError
from dsr_graph.formats import dsr_json
from dsr_graph.formats.state_store import StateStore
from dsr_graph.formats.world_files import read_world, write_world
from dsr_graph.model.binary import array_coercer, coerce_bytes, equal, size_of, to_json_value
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, ServerCore

VOCABULARY = {
    "format": "dsr-vocabulary",
    "version": 1,
    "extends": "default",
    "node_types": {"camera": "a camera"},
    "attributes": {
        "blob": "bytes",
        "image": {"type": "uint8_array", "volatile": True},
        "depth_image": {"type": "uint16_array", "volatile": True},
        "embedding": "float32_array",
    },
}
IMAGE = np.arange(4 * 5 * 3, dtype=np.uint8).reshape(4, 5, 3)
DEPTH = (np.arange(20, dtype=np.uint16) * 700).reshape(4, 5)


def vocabulary():
    return Vocabulary.from_json(VOCABULARY)


def dumps(doc):
    return json.dumps(doc, default=to_json_value)


def camera_core():
    core = ServerCore(Graph(vocabulary()))
    insert = {"op": "insert_node", "name": "cam", "type": "camera"}
    assert not isinstance(core.submit(dumps({"ops": [insert]})), Rejection)
    return core


def test_bytes_and_arrays_round_trip_through_json():
    assert coerce_bytes(b"\x00\xff") == b"\x00\xff"
    assert coerce_bytes(json.loads(dumps(b"\x00\xff"))) == b"\x00\xff"
    for type_name, value in (("uint8_array", IMAGE), ("uint16_array", DEPTH)):
        coerce = array_coercer(type_name)
        again = coerce(json.loads(dumps(coerce(value))))
        assert equal(again, value) and again.shape == value.shape
        assert not again.flags.writeable  # a value in the graph cannot change under it
    big_endian = DEPTH.astype(">u2")
    assert equal(array_coercer("uint16_array")(big_endian), DEPTH)  # stored little-endian
    assert size_of(IMAGE) == 60 and size_of(b"abc") == 3 and size_of("abc") == 0
    assert not equal(IMAGE, IMAGE.reshape(12, 5)) and not equal(IMAGE, IMAGE.tolist())


@pytest.mark.parametrize(
    ("type_name", "value", "named"),
    [
        ("bytes", "text", "expected bytes"),
        ("bytes", {"$bytes": "not base64!"}, "base64"),
        ("uint8_array", IMAGE.astype(np.float32), "array of uint8"),
        ("uint8_array", {"$array": "AAE=", "dtype": "uint16", "shape": [1]}, "uint16"),
        ("uint8_array", {"$array": "AAE=", "dtype": "uint8", "shape": [3]}, "has 3 bytes, got 2"),
        ("uint8_array", {"$array": "AAE=", "dtype": "uint8", "shape": [-2]}, "shape"),
        ("uint8_array", {"$array": "AAE=", "dtype": "uint8", "shape": "2"}, "shape"),
        ("uint8_array", [1, 2, 300], "must hold bytes"),
        ("uint8_array", "text", "expected an array of uint8"),
        ("float32_array", np.array([1.0, np.nan], np.float32), "finite"),
        ("uint8_array", np.uint8(3), "expected an array"),
    ],
)
def test_a_bad_binary_value_is_refused_by_name(type_name, value, named):
    coerce = coerce_bytes if type_name == "bytes" else array_coercer(type_name)
    with pytest.raises(ValueTypeError, match=named):
        coerce(value)


def test_a_transaction_sets_binary_values_and_its_delta_replays_them():
    core = camera_core()
    replica = Replica(core.graph.vocabulary)
    replica.load_snapshot(json.loads(dumps(core.snapshot())))
    attrs = {"image": IMAGE, "depth_image": DEPTH, "blob": b"\x01\x02"}
    delta = core.submit(dumps({"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": attrs}]}))
    assert not isinstance(delta, Rejection)
    stored = core.graph.node("cam").attrs
    assert equal(stored["image"], IMAGE) and stored["blob"] == b"\x01\x02"
    assert replica.receive(json.loads(dumps(delta))) != []
    mine = replica.graph.node("cam").attrs
    assert equal(mine["image"], IMAGE) and equal(mine["depth_image"], DEPTH)


def test_preconditions_compare_arrays_by_value():
    core = camera_core()
    same = np.array([0.5], np.float32)
    core.submit(
        dumps({"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": {"embedding": same}}]})
    )
    check = {"check": "attr_equals", "node": "cam", "attr": "embedding"}
    tx = {"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": {"blob": b"x"}}]}
    assert not isinstance(
        core.submit(dumps({**tx, "preconditions": [{**check, "value": same}]})), Rejection
    )
    other = np.array([0.25], np.float32)
    refused = core.submit(dumps({**tx, "preconditions": [{**check, "value": other}]}))
    assert isinstance(refused, Rejection)


def test_snapshots_world_files_and_the_journal_keep_binary_values(tmp_path):
    core = camera_core()
    attrs = {"image": IMAGE, "blob": b"\x00"}
    core.submit(dumps({"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": attrs}]}))
    text = dumps(core.snapshot())
    assert '"$array"' in text and '"dtype":"uint8"' in text.replace(" ", "")
    for trusted in (True, False):
        graph, _ = dsr_json.snapshot_from_json(json.loads(text), vocabulary(), trusted=trusted)
        assert equal(graph.node("cam").attrs["image"], IMAGE)
        assert graph.node("cam").attrs["blob"] == b"\x00"
    write_world(core.graph, tmp_path / "world.json")
    world = read_world(tmp_path / "world.json", vocabulary())
    assert world.violations == [] and equal(world.graph.node("cam").attrs["image"], IMAGE)

    store = StateStore(tmp_path / "state")
    store.open()
    store.write_snapshot(ServerCore(Graph(vocabulary())).durable_snapshot())
    replayed = ServerCore(Graph(vocabulary()))
    for delta in (
        replayed.submit(dumps({"ops": [{"op": "insert_node", "name": "cam", "type": "camera"}]})),
        replayed.submit(
            dumps({"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": {"blob": b"\x07"}}]})
        ),
    ):
        store.append(delta)
    store.close()
    again = StateStore(tmp_path / "state")
    again.open()
    restored, count, _ = ServerCore.restore(
        again.load_snapshot(), again.replay_journal, vocabulary()
    )
    assert count == 2 and restored.graph.node("cam").attrs["blob"] == b"\x07"
    again.close()


def test_a_value_over_the_size_limit_is_refused_and_changes_nothing():
    core = camera_core()
    core.max_value_bytes = 50
    before = dumps(core.snapshot())
    refused = core.submit(
        dumps({"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": {"image": IMAGE}}]})
    )
    assert isinstance(refused, Rejection) and "max_value_bytes" in refused.violation.message
    assert "60 bytes" in refused.violation.message and dumps(core.snapshot()) == before


def test_a_binary_type_given_a_plain_json_value_is_a_rule_violation():
    graph = Graph(vocabulary())
    graph.insert_node("cam", "camera")
    with pytest.raises(RuleViolation, match="image"):
        graph.set_node_attrs("cam", {"image": "a picture"})


def test_a_terminal_shows_a_binary_value_by_its_type_and_size():
    from dsr_graph.model.binary import short_text
    from dsr_graph.protocol.delta_text import delta_text

    assert short_text(IMAGE) == "<uint8 4x5x3>" and short_text(b"abc") == "<3 bytes>"
    assert short_text(json.loads(dumps(IMAGE))) == "<uint8 4x5x3>" and short_text(2) == "2"
    delta = json.loads(
        dumps(
            {
                "seq": 3,
                "agent": "/camera",
                "ops": [{"op": "set_node_attrs", "node": "cam", "attrs": {"image": IMAGE}}],
            }
        )
    )
    assert "cam {image=<uint8 4x5x3>}" in delta_text(delta)


def test_dsr_get_blob_answers_a_values_bytes_type_and_shape_or_says_why_not():
    from dsr_graph.protocol.blobs import binary_value
    from dsr_graph.protocol.queries import read_binary

    core = camera_core()
    attrs = {"image": IMAGE, "blob": b"\x01\x02", "name": "front"}
    assert not isinstance(
        core.submit(dumps({"ops": [{"op": "set_node_attrs", "node": "cam", "attrs": attrs}]})),
        Rejection,
    )
    image = read_binary(core.graph, "cam", "image")
    assert (image.found, image.dtype, image.shape) == (True, "uint8", (4, 5, 3))
    assert equal(binary_value(image.dtype, image.shape, image.data), IMAGE)
    raw = read_binary(core.graph, "cam", "blob")
    assert (raw.dtype, raw.shape, raw.data) == ("bytes", (), b"\x01\x02")
    assert "not a binary value" in read_binary(core.graph, "cam", "name").error
    assert "no attribute 'depth_image'" in read_binary(core.graph, "cam", "depth_image").error
    assert read_binary(core.graph, "nobody", "image").error == "no node 'nobody'"
