"""HighToLow of the Get Up & Go (pure): the test node of a Get Up & Go and its ``gait`` node, where
PELEA starts and abandons the trials the gait analyser times. What every test shares is
``test_node.py``."""

from __future__ import annotations

from typing import Any

from clarc_agents.gug.record import KIND
from clarc_agents.test_node import patient_attrs, take_request
from dsr_graph.model.graph import Graph


# ------------------------------------------------------------------ HighToLow for the trial
def start_test(graph: Graph, patient: str, started: str) -> dict[str, Any]:
    """The test node says a Get Up & Go test runs; a fresh gait node (a previous test's result
    goes). Takes the Start request for ``patient`` (CAS)."""
    forget, patient_id = patient_attrs(graph)
    checks, ops = take_request(graph, patient)
    ops = forget + ops
    if "finished" in graph.node("test").attrs:
        ops.append({"op": "remove_node_attrs", "node": "test", "names": ["finished"]})
    attrs = {
        **patient_id,
        "patient": patient,
        "kind": KIND,
        "status": "running",
        "started": started,
        "explained": False,
        "said_goodbye": False,
        "clinician_called": False,
        "person_lost_count": 0,
        "void_reasons": [],
    }
    ops.append({"op": "set_node_attrs", "node": "test", "attrs": attrs})
    if "gait" in graph:
        ops.append({"op": "delete_node", "node": "gait"})
    gait = {"status": "idle", "trial": 0, "phase": ""}
    ops.append({"op": "insert_node", "name": "gait", "type": "gait", "attrs": gait})
    ops.append({"op": "insert_edge", "from": "test", "to": "gait", "type": "has"})
    return {"preconditions": checks, "ops": ops}


def time_trial(trial: int, go_at: float) -> dict[str, Any]:
    """Trial ``trial`` begins: the gait analyser times it from ``go_at`` (epoch seconds)."""
    attrs = {"status": "timing", "trial": trial, "go_at": go_at, "phase": "waiting"}
    return {"ops": [{"op": "set_node_attrs", "node": "gait", "attrs": attrs}]}


def void_trial(trial: int) -> dict[str, Any]:
    """Trial ``trial`` is abandoned, unless the analyser timed it first (CAS)."""
    return {
        "preconditions": [
            {"check": "attr_equals", "node": "gait", "attr": "trial", "value": trial},
            {"check": "attr_equals", "node": "gait", "attr": "status", "value": "timing"},
        ],
        "ops": [{"op": "set_node_attrs", "node": "gait", "attrs": {"status": "void"}}],
    }
