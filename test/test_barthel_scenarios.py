"""The whole robot through the README's main job (scripts/launch.sh: every node its own process),
one test per scenario, checking the stored result field by field."""

import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent


def item(name, points, via, attempts):
    return {"item": name, "points": points, "via": via, "attempts": attempts}


EXPECTED = {
    "default.yaml": {
        "patient": "Carlos", "total": 80, "band": "moderate", "unanswered": ["grooming"],
        "clinician_called": False, "person_lost": True,
        "items": [item("feeding", 10, "voice", 1), item("bathing", 0, "touch", 1), item("grooming", None, None, 2),
                  item("dressing", 5, "voice", 2), item("bowels", 10, "voice", 2), item("bladder", 10, "voice", 1),
                  item("toilet_use", 10, "voice", 1), item("transfers", 15, "voice", 1),
                  item("mobility", 15, "voice", 1), item("stairs", 5, "touch", 1)]},
    "all_voice.yaml": {
        "patient": "Ana", "total": 100, "band": "independent", "unanswered": [],
        "clinician_called": False, "person_lost": False,
        "items": [item("feeding", 10, "voice", 1), item("bathing", 5, "voice", 1), item("grooming", 5, "voice", 1),
                  item("dressing", 10, "voice", 1), item("bowels", 10, "voice", 1), item("bladder", 10, "voice", 1),
                  item("toilet_use", 10, "voice", 1), item("transfers", 15, "voice", 1),
                  item("mobility", 15, "voice", 1), item("stairs", 10, "voice", 1)]},
    "two_unanswered.yaml": {
        "patient": "Luis", "total": 70, "band": "moderate", "unanswered": ["grooming", "bladder"],
        "clinician_called": True, "person_lost": False,
        "items": [item("feeding", 5, "touch", 1), item("bathing", 5, "voice", 1), item("grooming", None, None, 2),
                  item("dressing", 10, "voice", 1), item("bowels", 10, "voice", 1), item("bladder", None, None, 2),
                  item("toilet_use", 10, "voice", 1), item("transfers", 15, "voice", 1),
                  item("mobility", 15, "voice", 1), item("stairs", 0, "voice", 1)]},
    "not_understood.yaml": {
        "patient": "Marta", "total": 75, "band": "moderate", "unanswered": ["bathing"],
        "clinician_called": False, "person_lost": False,
        "items": [item("feeding", 5, "voice", 2), item("bathing", None, None, 2), item("grooming", 5, "voice", 1),
                  item("dressing", 10, "voice", 1), item("bowels", 10, "voice", 1), item("bladder", 10, "voice", 1),
                  item("toilet_use", 10, "voice", 1), item("transfers", 10, "touch", 2),
                  item("mobility", 5, "voice", 2), item("stairs", 10, "voice", 1)]},
    "walks_away.yaml": {
        "patient": "Pedro", "total": 95, "band": "slight", "unanswered": [],
        "clinician_called": False, "person_lost": True, "person_lost_count": 3,
        "items": [item("feeding", 10, "voice", 1), item("bathing", 5, "voice", 1), item("grooming", 5, "voice", 1),
                  item("dressing", 10, "voice", 1), item("bowels", 5, "touch", 1), item("bladder", 10, "voice", 1),
                  item("toilet_use", 10, "voice", 1), item("transfers", 15, "voice", 1),
                  item("mobility", 15, "voice", 1), item("stairs", 10, "voice", 1)]},
}


@pytest.mark.parametrize("scenario", sorted(EXPECTED))
def test_scenario_through_the_launch(scenario, tmp_path):
    from ros_processes import fresh_domain_id

    db = tmp_path / "cgamed.sqlite"
    env = dict(os.environ, ROS_DOMAIN_ID=str(fresh_domain_id()))
    run = subprocess.run([str(REPO / "scripts" / "launch.sh"), "--scenario", str(REPO / "scenarios" / scenario),
                          "--db", str(db), "--timeout", "150", "--run-dir", str(tmp_path / "run")],
                         capture_output=True, text=True, timeout=240, env=env)
    logs = "\n".join(f"--- {p.name}\n{p.read_text()[-3000:]}" for p in sorted((tmp_path / "run" / "log").glob("*.log")))
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:] + logs
    assert "RESULT" in run.stdout and "Barthel index" in run.stdout
    listed = subprocess.run(["clarc", "results", "--db", str(db), "--json"], capture_output=True, text=True, timeout=60, env=env)
    [stored] = json.loads(listed.stdout)
    expected = EXPECTED[scenario]
    for key, value in expected.items():
        assert stored[key] == value, f"{key}: {stored[key]!r} != {value!r}\n{run.stdout[-4000:]}"
    assert stored["started"] < stored["finished"]
    assert sum(i["points"] or 0 for i in stored["items"]) == stored["total"]
