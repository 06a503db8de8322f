"""The DSR layout every test shares (pure): the test node (the clinician's Start request waiting
on it, the test running or finished, its progress, the clinician called) and whether the person
is with the robot. The core of PELEA (``pelea/``) reads and writes it for every test; each test
adds its own layout (``questionnaire/high_to_low.py``, ``gug/high_to_low.py``)."""

from __future__ import annotations

from typing import Any

from dsr_graph.model.graph import Graph

REQUEST = (
    "requested_patient",
    "requested",
    "requested_test",
    "requested_patient_id",
    "requested_language",
)


def request_start(
    patient: str,
    requested: str,
    test: str = "barthel",
    patient_id: int | None = None,
    graph: Graph | None = None,
    language: str = "en",
) -> dict[str, Any]:
    """The clinician pressed Start for a test (``barthel``, ``mmse``, ``get_up_and_go``, ...)
    and a patient (their record's id, if the Start named one): the request waits on the test
    node until PELEA takes it, in ``language`` (en, or another the test is shipped in).
    ``graph``: the DSR as the sender sees it, so that an id left by an earlier request not taken
    yet goes."""
    attrs: dict[str, Any] = {
        "requested_patient": patient,
        "requested": requested,
        "requested_test": test,
        "requested_language": language,
    }
    ops: list[dict[str, Any]] = []
    if patient_id is not None:
        attrs["requested_patient_id"] = patient_id
    elif graph is not None and "requested_patient_id" in graph.node("test").attrs:
        ops.append({"op": "remove_node_attrs", "node": "test", "names": ["requested_patient_id"]})
    return {"ops": ops + [{"op": "set_node_attrs", "node": "test", "attrs": attrs}]}


def patient_attrs(graph: Graph) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """The patient's record id from the Start request onto the running test (ops removing an
    earlier test's id first, attrs to set): results name the record, not only the name."""
    test = graph.node("test").attrs
    if "requested_patient_id" in test:
        return [], {"patient_id": int(test["requested_patient_id"])}
    if "patient_id" in test:
        return [{"op": "remove_node_attrs", "node": "test", "names": ["patient_id"]}], {}
    return [], {}


def take_request(graph: Graph, patient: str) -> tuple[list[dict], list[dict]]:
    """(preconditions, ops) taking the Start request for ``patient`` (CAS on it), if any."""
    test = graph.node("test")
    if "requested_patient" not in test.attrs:
        return [], []
    check = {"check": "attr_equals", "node": "test", "attr": "requested_patient", "value": patient}
    names = [n for n in REQUEST if n in test.attrs]
    return [check], [{"op": "remove_node_attrs", "node": "test", "names": names}]


def refuse_start(graph: Graph, patient: str) -> dict[str, Any]:
    """A Start while a test runs: the request is dropped (CAS on the same request)."""
    checks, ops = take_request(graph, patient)
    return {"preconditions": checks, "ops": ops}


def record_test(**attrs: Any) -> dict[str, Any]:
    """Progress of the test on its node (greeted, explained, said_goodbye, person_lost_count,
    finished): what a restarted PELEA reads to go on from where the test was."""
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": attrs}]}


def call_clinician(graph: Graph) -> dict[str, Any]:
    ops: list[dict[str, Any]] = [
        {"op": "set_node_attrs", "node": "test", "attrs": {"clinician_called": True}}
    ]
    if graph.edge("test", "clinician", "requests") is None:
        ops.append({"op": "insert_edge", "from": "test", "to": "clinician", "type": "requests"})
    return {"ops": ops}


def finish_test(graph: Graph) -> dict[str, Any]:
    """The result is stored: the test is over."""
    ops: list[dict[str, Any]] = [
        {"op": "set_node_attrs", "node": "test", "attrs": {"status": "finished"}}
    ]
    if graph.edge("test", "clinician", "requests") is not None:
        ops.append({"op": "delete_edge", "from": "test", "to": "clinician", "type": "requests"})
    return {"ops": ops}


def person_present(graph: Graph) -> bool:
    """The person is in front of the robot (Person's ``person is_with robot``)."""
    return graph.edge("person", "robot", "is_with") is not None


# ------------------------------------------------------------------ the test as the DSR holds it
def start_request(graph: Graph) -> str | None:
    """The patient for whom Start was pressed and not yet taken, if any."""
    test = graph.find("test")
    return None if test is None else test.attrs.get("requested_patient")


def requested_language(graph: Graph, default: str = "en") -> str:
    """The language the waiting Start asked for (``default`` when it named none)."""
    return str(graph.node("test").attrs.get("requested_language", default))


def requested_test(graph: Graph) -> str:
    """Which test the pending Start is for (a request without one is for the Barthel test)."""
    return str(graph.node("test").attrs.get("requested_test", "barthel"))


def running_test(graph: Graph) -> str:
    """Which test the test node holds (written before tests had kinds: the Barthel test)."""
    return str(graph.node("test").attrs.get("kind", "barthel"))


def test_running(graph: Graph) -> bool:
    test = graph.find("test")
    return test is not None and test.attrs.get("status") == "running"
