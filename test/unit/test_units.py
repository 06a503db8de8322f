"""Lengths: files declare their unit, the DSR holds metres, CORTEX's millimetres are converted
once when read and back when written; a state directory from before units were declared is
converted, not misread."""

import json

import numpy as np
import pytest

from dsr_graph.exceptions import FormatError
from dsr_graph.formats import dsr_json
from dsr_graph.formats.cortex import from_cortex, to_cortex
from dsr_graph.formats.state_store import StateStore
from dsr_graph.formats.world_files import read_world, write_world
from dsr_graph.protocol.server_core import ServerCore


def world(unit=None, translation=(2000, 1500, 0), rt_form="euler"):
    rt = {"translation": list(translation), "rotation_euler_xyz": [0, 0, 0]}
    if rt_form == "matrix":
        m = np.eye(4)
        m[:3, 3] = translation
        rt = {"matrix": m.tolist()}
    doc = {
        "format": "dsr-graph",
        "version": 1,
        "kind": "world",
        "nodes": [{"name": "room", "type": "room"}, {"name": "robot", "type": "robot"}],
        "edges": [{"from": "room", "to": "robot", "type": "RT", "rt": rt}],
    }
    if unit is not None:
        doc["units"] = {"length": unit}
    return doc


@pytest.mark.parametrize(
    ("unit", "translation"),
    [("m", (2, 1.5, 0)), ("cm", (200, 150, 0)), ("mm", (2000, 1500, 0)), (None, (2000, 1500, 0))],
)
@pytest.mark.parametrize("rt_form", ["euler", "matrix"])
def test_every_declared_unit_loads_as_metres(unit, translation, rt_form):
    graph, violations = dsr_json.from_json(world(unit, translation, rt_form))
    assert not violations
    assert graph.transform("room", "robot")[:3, 3].tolist() == [2.0, 1.5, 0.0]


@pytest.mark.parametrize(
    ("declared", "fragment"),
    [({"length": "inch"}, "units.length"), ("mm", '"units" must be'), ({"size": "m"}, "units")],
)
def test_a_bad_units_declaration_is_named(declared, fragment):
    doc = world()
    doc["units"] = declared
    with pytest.raises(FormatError, match=fragment):
        dsr_json.from_json(doc)


def test_what_we_write_says_metres_and_reads_back_the_same(tmp_path):
    graph, _ = dsr_json.from_json(world("mm"))
    write_world(graph, tmp_path / "w.json")
    doc = json.loads((tmp_path / "w.json").read_text())
    assert doc["units"] == {"length": "m"}
    again = read_world(tmp_path / "w.json").graph
    assert np.array_equal(again.transform("room", "robot"), graph.transform("room", "robot"))
    snapshot = dsr_json.to_json(graph, "snapshot", seq=3)
    back, _ = dsr_json.snapshot_from_json(snapshot, trusted=True)
    assert back.transform("room", "robot")[:3, 3].tolist() == [2.0, 1.5, 0.0]


def test_cortex_millimetres_are_converted_when_read_and_written_back_as_millimetres():
    graph, _ = dsr_json.from_json(world("m", (0.35, 1.2, 0)))
    cortex = to_cortex(graph)
    links = [link for s in cortex["DSRModel"]["symbols"].values() for link in s["links"]]
    assert links[0]["linkAttribute"]["rt_translation"]["value"] == [350.0, 1200.0, 0.0]
    back, _ = from_cortex(cortex)
    assert np.allclose(back.transform("room", "robot")[:3, 3], [0.35, 1.2, 0])


def test_a_state_dir_from_before_units_is_converted_to_metres(tmp_path):
    """What dsr_server does on restart: snapshot (no units: mm) and journal (mm RTs)."""
    graph, _ = dsr_json.from_json(world("mm"))
    old = dsr_json.to_json(graph, "snapshot", seq=0)
    del old["units"]
    old["edges"][0]["rt"] = {"translation": [2000, 1500, 0], "rotation_euler_xyz": [0, 0, 0]}
    store = StateStore(tmp_path)
    store.open()
    store.write_snapshot(old)
    store.append(
        {
            "seq": 1,
            "ops": [
                {
                    "op": "set_rt",
                    "from": "room",
                    "to": "robot",
                    "rt": {"translation": [2500, 1500, 0], "rotation_euler_xyz": [0, 0, 0]},
                }
            ],
        }
    )
    store.flush()
    core, replayed, converted = ServerCore.restore(store.load_snapshot(), store.replay_journal)
    assert (replayed, converted) == (1, True)
    assert core.graph.transform("room", "robot")[:3, 3].tolist() == [2.5, 1.5, 0.0]
    # stored again as the server does: declared in metres, converted once
    store.write_snapshot(core.durable_snapshot())
    again, _, converted = ServerCore.restore(store.load_snapshot(), store.replay_journal)
    assert not converted and again.graph.transform("room", "robot")[:3, 3].tolist() == [2.5, 1.5, 0]
