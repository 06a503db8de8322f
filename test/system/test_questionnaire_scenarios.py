"""The MMSE and the Lawton scale through the README's main job (scripts/launch.sh, every node its
own process): each shipped scenario's stored result (`clarc results --json`) against the
scenario itself: every item earns the points the patient gave, the way they gave them, after
the tries its deviations cost; the drawings wait for the clinician."""

from pathlib import Path

import pytest

from clarc_agents import definitions
from clarc_sim.patient.scenario import load

REPO = Path(__file__).resolve().parents[2]
SCENARIOS = sorted(p.name for p in (REPO / "scenarios").glob("mmse_*.yaml")) + ["lawton.yaml"]


def expected(scenario) -> dict:
    """Each item as the stored result must give it: (points, via, attempts)."""
    definition = definitions.load(scenario.test)
    out = {}
    for item in definition.items:
        plan = scenario.plan(item.key)
        attempts = 2 if plan.first or plan.via == "silence" else 1
        if item.kind == "eyes" and (plan.via == "silence" or plan.answer == 0):
            out[item.key] = (0, "camera", 2)  # asked twice, the eyes never closed: 0 points
        elif plan.via == "silence":
            out[item.key] = (None, None, attempts)
        elif item.needs_clinician:
            out[item.key] = (None, plan.via, attempts)
        else:
            out[item.key] = (plan.answer, plan.via, attempts)
    return out


def test_the_shipped_mmse_scenarios_cover_every_item_and_path():
    mmse = definitions.load("mmse")
    loaded = [load(str(REPO / "scenarios" / s)) for s in SCENARIOS if s.startswith("mmse")]
    plans = [s.plan(i.key) for s in loaded for i in mmse.items]
    for item in mmse.items:  # every item both earned whole and not
        earned = {s.plan(item.key).answer for s in loaded}
        assert item.max in earned and min(p for p in earned if p is not None) < item.max, item.key
    assert {p.first for p in plans} >= {"garbled", "silence"}
    assert any(p.leave is not None for p in plans) and any(p.via == "silence" for p in plans)


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_a_questionnaire_scenario_through_the_launch(scenario, tmp_path):
    from ros_processes import launch_scenario

    run, [stored] = launch_scenario(REPO / "scenarios" / scenario, tmp_path)
    truth = load(str(REPO / "scenarios" / scenario))
    assert stored["test"] == truth.test and stored["patient"] == truth.patient
    got = {i["item"]: (i["points"], i["via"], i["attempts"]) for i in stored["items"]}
    assert got == expected(truth), run.stdout[-3000:]
    definition = definitions.load(truth.test)
    assert {i["item"]: i["max"] for i in stored["items"]} == {
        i.key: i.max for i in definition.items
    }
    assert stored["total"] == sum(p for p, _, _ in got.values() if p is not None)
    waiting = [i for i in stored["items"] if i["needs_clinician"] and i["points"] is None]
    assert stored["complete"] is (not waiting)
    assert all(
        i["needs_clinician"] == (i["item"] in ("writing", "copying")) for i in stored["items"]
    )
    assert "RESULT" in run.stdout and definition.title in run.stdout
    # asked in the scenario's language: how the robot introduces a question
    assert {"en": "CLARC: Question ", "es": "CLARC: Pregunta "}[truth.language] in run.stdout
    assert stored["person_lost"] == any(truth.plan(k).leave is not None for k in definition.order)


def test_pelea_drops_a_start_for_a_test_it_does_not_run_saying_so(ros):
    from clarc_agents.test_node import request_start

    from ros_processes import agent_in_session, send_and_wait, snapshot_via, wait_for

    ros.procs.start_server(ros.tmp / "state", world=REPO / "worlds" / "clarc_room.json")
    snapshot_via(ros.session, timeout=20)
    ros.procs.start("pelea", ["pelea", "--ros-args", "-p", f"outbox_dir:={ros.tmp / 'outbox'}"])
    log = ros.tmp / "pelea.log"
    wait_for(lambda: "PELEA up" in log.read_text(errors="replace"), 30, "PELEA")
    agent = agent_in_session(ros)
    request = request_start("Ana", "2026-11-24T10:00:00+00:00", "moca")
    assert send_and_wait(ros, agent, request).accepted
    wait_for(
        lambda: "requested_patient" not in agent.graph.node("test").attrs,
        20,
        "the Start dropped",
        ros.session,
    )
    assert "no test 'moca' here (barthel, lawton, mmse, get_up_and_go); refused" in log.read_text()
    assert agent.graph.node("test").attrs.get("status") != "running"
