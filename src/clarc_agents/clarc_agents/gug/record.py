"""A Get Up & Go test as the DSR holds it (pure; LowToHigh for PELEA, and what observers read):
the test node (patient, started, person_lost_count) and the gait node the analyser writes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from clarc_agents.gug.phases import PHASES, STILL
from dsr_graph.model.graph import Graph

KIND = "get_up_and_go"
TIMED, UNABLE = "timed", "unable"
UNABLE_BAND = "unable to perform"


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
    """The stored result, read from the DSR (the test node and the analyser's gait node):
    ``outcome: timed`` with the trial's times, or ``outcome: unable`` when no trial could be
    timed (every void trial's reason in ``void_reasons``)."""
    g, t = gait(graph), graph.node("test").attrs
    lost = int(t.get("person_lost_count", 0))
    patient_id = {"patient_id": int(t["patient_id"])} if "patient_id" in t else {}
    doc = {
        **patient_id,
        "test": KIND,
        "patient": str(t.get("patient", record.patient)),
        "started": str(t.get("started", record.started)),
        "finished": t.get("finished"),
    }
    if g.get("status") == "timed":
        phases = [float(s) for s in g["phase_seconds"]]
        doc |= {
            "outcome": TIMED,
            "tug_seconds": float(g["tug_seconds"]),
            "reaction_seconds": float(g.get("reaction_seconds", 0.0)),
            "phases": {
                **dict(zip(PHASES, phases, strict=True)),
                STILL: float(g.get("still_seconds", 0.0)),
            },
            "band": str(g["band"]),
            "fall_risk": bool(g["fall_risk"]),
        }
    else:  # a patient who cannot do the test is at risk of falling (STEADI: unable = at risk)
        doc |= {
            "outcome": UNABLE,
            "tug_seconds": None,
            "reaction_seconds": None,
            "phases": None,
            "band": UNABLE_BAND,
            "fall_risk": True,
        }
    return doc | {
        "trials": int(g.get("trial", 0)),
        "void_reasons": [str(r) for r in t.get("void_reasons", [])],
        "clinician_called": bool(t.get("clinician_called", record.clinician_called)),
        "person_lost": lost > 0,
        "person_lost_count": lost,
    }
