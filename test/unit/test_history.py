"""The viewer's history: the graph at any past seq, deltas since a seq, and gaps refused."""

import json

import pytest

from dsr_graph.exceptions import SeqUnavailable
from dsr_graph.formats import dsr_json
from dsr_graph.model.graph import Graph
from dsr_graph.protocol import history
from dsr_graph.protocol.history import History
from dsr_graph.protocol.server_core import ServerCore


def deltas(n):
    core = ServerCore(Graph())
    start = core.snapshot()
    return start, [
        core.submit(
            json.dumps({"ops": [{"op": "insert_node", "name": f"n{i}", "type": "transform"}]})
        )
        for i in range(n)
    ]


def test_graph_at_every_past_seq_across_checkpoints(monkeypatch):
    monkeypatch.setattr(history, "CHECKPOINT_EVERY", 4)
    start, ds = deltas(11)
    h = History()
    h.reset(start)
    for d in ds:
        h.add(d)
    assert (h.first_seq, h.seq) == (0, 11)
    for seq in range(12):
        assert sorted(n.name for n in h.graph_at(seq).nodes()) == sorted(
            f"n{i}" for i in range(seq)
        )
    assert [d["seq"] for d in h.since(8)] == [9, 10, 11]
    assert [d["seq"] for d in h.since(0, limit=2)] == [1, 2]
    with pytest.raises(SeqUnavailable):
        h.graph_at(12)


def test_a_gap_after_a_resync_is_refused_not_guessed():
    start, ds = deltas(6)
    h = History()
    h.reset(start)
    h.add(ds[0])
    with pytest.raises(SeqUnavailable):
        h.add(ds[2])  # seq 2 never came
    later, _ = dsr_json.snapshot_from_json(
        json.loads(json.dumps(start))
    )  # build the state at seq 4
    core = ServerCore(later)
    for d in ds[:4]:
        core.replay(d)
    h.reset(core.snapshot())  # the replica resynchronised at seq 4
    h.add(ds[4])
    assert (
        h.seq == 5
        and len(h.graph_at(5)) == 5
        and len(h.graph_at(4)) == 4
        and len(h.graph_at(1)) == 1
    )
    with pytest.raises(SeqUnavailable, match="gap"):
        h.graph_at(2)


def test_a_history_reset_from_a_live_graph_shares_nothing_with_it():
    core = ServerCore(Graph())
    replica = Graph()
    add = core.submit(
        json.dumps(
            {
                "ops": [
                    {"op": "insert_node", "name": "n", "type": "transform", "attrs": {"level": 1}}
                ]
            }
        )
    )
    from dsr_graph.model.transaction import apply_ops

    apply_ops(replica, add["ops"])
    h = History()
    h.reset(dsr_json.to_json(replica, "snapshot", seq=1))  # as the viewer does on a resync
    remove = core.submit(
        json.dumps({"ops": [{"op": "remove_node_attrs", "node": "n", "names": ["level"]}]})
    )
    apply_ops(replica, remove["ops"])  # the replica applies the delta first...
    h.add(remove)  # ...and the history must still find the attribute to remove
    assert h.graph.node("n").attrs == {} and replica.node("n").attrs == {}
    assert h.graph_at(1).node("n").attrs == {"level": 1}
