"""A Get Up & Go test as the DSR holds it (pure; LowToHigh for PELEA, and what observers read):
the test node (patient, started, person_lost_count) and the gait node the analyser writes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from clarc_agents.gug.phases import PHASES
from dsr_graph.model.graph import Graph

KIND = "get_up_and_go"


@dataclass
class GugRecord:
    """What the executive keeps of the test (the rest is on the gait node)."""

    patient: str
    started: str
    person_lost_count: int = 0
    clinician_called: bool = False
    finished: str | None = None


def gait(graph: Graph) -> dict[str, Any]:
    node = graph.find("gait")
    return {} if node is None else dict(node.attrs)


def result(graph: Graph, record: GugRecord) -> dict[str, Any]:
    """The stored result, read from the DSR (the test node and the analyser's gait node)."""
    g, t = gait(graph), graph.node("test").attrs
    lost = int(t.get("person_lost_count", 0))
    patient_id = {"patient_id": int(t["patient_id"])} if "patient_id" in t else {}
    return {
        **patient_id,
        "test": KIND,
        "patient": str(t.get("patient", record.patient)),
        "started": str(t.get("started", record.started)),
        "finished": t.get("finished"),
        "tug_seconds": float(g["tug_seconds"]),
        "phases": dict(zip(PHASES, (float(s) for s in g["phase_seconds"]), strict=True)),
        "band": str(g["band"]),
        "fall_risk": bool(g["fall_risk"]),
        "trials": int(g.get("trial", 1)),
        "person_lost": lost > 0,
        "person_lost_count": lost,
    }
