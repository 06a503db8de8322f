"""The viewer and the clinician's dashboard in a real browser (headless Chromium + Playwright)."""

import json
import os
import subprocess
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path

import pytest

from clarc_agents.gug.skeleton import JOINTS, parse_skeleton, skeleton_tx

from browser import chromium_page, free_port
from ros_processes import (
    agent_in_session,
    fresh_domain_id,
    send_and_wait,
    snapshot_via,
    stored_tests,
    wait_for,
)

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "clarc_room.json"


def http_json(url):
    with urllib.request.urlopen(url, timeout=5) as r:
        return json.loads(r.read())


@pytest.fixture
def viewer(ros):
    ros.procs.start_server(ros.tmp / "state", world=WORLD)
    snapshot_via(ros.session, timeout=20)
    port = free_port()
    ros.procs.start("viewer", ["dsr_viewer", "--ros-args", "-p", f"port:={port}"])
    url = f"http://127.0.0.1:{port}/"

    def up():
        try:
            return http_json(url + "api/graph")["seq"] == 0
        except OSError:
            return False

    wait_for(up, 20, "the viewer to serve the graph")
    return url


def test_api_graph_is_the_current_snapshot(ros, viewer):
    doc = http_json(viewer + "api/graph")
    assert doc["format"] == "dsr-graph" and doc["kind"] == "snapshot"
    assert {n["name"] for n in doc["nodes"]} >= {"room", "robot", "kinect", "speaking", "showing"}
    t = http_json(viewer + "api/transform?from=room&to=kinect")
    assert t["translation"] == [2.1, 1.5, 1.2] and t["chain"] == [
        "room",
        "robot",
        "kinect",
    ]


def test_viewer_shows_a_change_within_a_second_and_scrubs_back(ros, viewer):
    agent = agent_in_session(ros)
    with chromium_page() as page:
        page.goto(viewer)
        page.wait_for_function("Number(document.body.dataset.nodes) === 14", timeout=15000)
        assert (
            page.evaluate("window.dsrViewer.cy.edges('.rt').length") == 7
        )  # the RT tree, drawn apart
        page.wait_for_timeout(500)  # the live stream is open

        result = send_and_wait(
            ros,
            agent,
            {
                "ops": [
                    {"op": "insert_node", "name": "visitor", "type": "person"},
                    {
                        "op": "insert_edge",
                        "from": "kinect",
                        "to": "visitor",
                        "type": "RT",
                        "rt": {"translation": [0.9, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]},
                    },
                    {"op": "insert_edge", "from": "visitor", "to": "robot", "type": "is_with"},
                ]
            },
        )
        accepted = time.monotonic()
        assert result.accepted
        page.wait_for_function(
            "window.dsrViewer.cy.getElementById('n:visitor').nonempty()", timeout=1000
        )
        print(
            f"viewer showed the change {1000 * (time.monotonic() - accepted):.0f} ms "
            "after it was accepted"
        )
        assert page.evaluate(
            "window.dsrViewer.cy.getElementById('e:visitor|is_with|robot').nonempty()"
        )
        assert page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').hasClass('flash')")

        send_and_wait(
            ros,
            agent,
            {"ops": [{"op": "set_node_attrs", "node": "visitor", "attrs": {"patient": "Carlos"}}]},
        )
        page.wait_for_function("document.body.dataset.seq === '2'", timeout=3000)
        assert page.locator("#deltas li").count() == 2

        # the inspector: attributes, version, pose in another node's frame
        page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').emit('tap')")
        page.wait_for_selector("#node-table")
        table = page.inner_text("#node-table")
        assert "version\t2" in table and "patient\tCarlos" in table
        page.select_option("#frame", "room")
        page.wait_for_function(
            "document.getElementById('pose').dataset.translation && Math.abs("
            "JSON.parse(document.getElementById('pose').dataset.translation)[0] - 3.0) < 1e-9",
            timeout=3000,
        )
        assert "] m\n" in page.inner_text("#pose")  # the DSR's unit, said

        # scrub back to seq 0: the visitor is not there yet; back to live: it is
        page.locator("#scrub").fill("0")
        page.wait_for_function("document.body.dataset.shownSeq === '0'", timeout=3000)
        assert page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').empty()")
        assert "past" in page.inner_text("#status")
        page.click("#deltas li[data-seq='1']")
        page.wait_for_function("document.body.dataset.shownSeq === '1'", timeout=3000)
        assert page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').nonempty()")
        page.click("#live")
        page.wait_for_function(
            "document.body.dataset.live === 'true' && document.body.dataset.shownSeq === '2'",
            timeout=3000,
        )

        # a skeleton frame (Get Up & Go): every joint a geometric node under the person
        skeleton = {
            joint: {"p": [900.0 + 10 * i, 20.0 * (i % 3), -400.0 + 50 * i], "c": 0.9}
            for i, joint in enumerate(JOINTS)
        }
        person = {"translation": [0.9, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]}
        send_and_wait(
            ros,
            agent,
            {
                "ops": [
                    {"op": "insert_node", "name": "person", "type": "person"},
                    {
                        "op": "insert_edge",
                        "from": "kinect",
                        "to": "person",
                        "type": "RT",
                        "rt": person,
                    },
                ]
            },
        )
        send_and_wait(ros, agent, skeleton_tx(agent.graph, parse_skeleton(skeleton), 1.0))
        page.wait_for_function(
            "window.dsrViewer.cy.getElementById('n:person_knee_left').nonempty()", timeout=3000
        )
        rt_edges = page.evaluate("window.dsrViewer.cy.edges('.rt').length")
        assert rt_edges == 9 + len(JOINTS)  # the room's, the visitor, the person, its joints
        page.evaluate("window.dsrViewer.cy.getElementById('n:person_knee_left').emit('tap')")
        page.wait_for_selector("#pose")
        page.select_option("#frame", "kinect")
        page.wait_for_function(  # the knee where the Kinect saw it, in metres (0.1 mm kept)
            "document.getElementById('pose').dataset.translation && Math.abs("
            "JSON.parse(document.getElementById('pose').dataset.translation)[0] - 0.98) < 1e-3",
            timeout=3000,
        )


def test_dashboard_starts_a_test_and_shows_it_complete(tmp_path):
    db = tmp_path / "cgamed.sqlite"
    port = free_port()
    env = dict(os.environ, ROS_DOMAIN_ID=str(fresh_domain_id()))
    launch = subprocess.Popen(
        [
            str(REPO / "scripts" / "launch.sh"),
            "--wait-start",
            "--db",
            str(db),
            "--timeout",
            "150",
            "--run-dir",
            str(tmp_path / "run"),
            "--viewer-port",
            str(free_port()),
            "--dashboard-port",
            str(port),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )
    try:
        url = f"http://127.0.0.1:{port}/"

        def up():
            try:
                return http_json(url + "api/status")["running"] is False
            except OSError:
                return False

        wait_for(up, 60, "the dashboard")
        with chromium_page() as page:
            page.goto(url)
            page.click("#start")  # no patient chosen yet
            page.wait_for_function(
                "document.getElementById('start-error').textContent.includes('choose a patient')"
            )
            page.fill("#new-patient", "Carlos")
            page.click("#add-patient")
            page.wait_for_function("document.getElementById('patient-id').value !== ''")
            page.select_option("#test", "barthel")
            page.click("#start")
            page.wait_for_selector("body[data-running=true]", timeout=20000)
            page.wait_for_function(
                "document.getElementById('live-item').textContent.includes('/10')", timeout=30000
            )
            page.wait_for_selector("body[data-running=false]", timeout=120000)
            page.wait_for_function("Number(document.body.dataset.results) === 1", timeout=10000)
            events = page.inner_text("#events")
            assert "the patient left" in events and "finished: 80/100 (moderate)" in events
            assert "grooming: no answer (try 2)" in events  # read from the DSR's item node
            page.click("#results tbody tr")
            page.wait_for_selector("#items")
            items = page.inner_text("#items")
            assert "Grooming" in items and "I use stairs by myself" not in items
            grooming = page.inner_text("#items tr[data-item='grooming']")
            stairs = page.inner_text("#items tr[data-item='stairs']")
            assert "unanswered" in grooming and "2 tries" in grooming
            assert "I need help on stairs\t5/10\ttouch" in stairs  # the option in words
        out, _ = launch.communicate(timeout=60)
        assert launch.returncode == 0, out[-3000:]
    finally:
        if launch.poll() is None:
            launch.terminate()
            launch.wait(timeout=30)
    stored = stored_tests(db)
    assert [t["patient"] for t in stored] == ["Carlos"] and stored[0]["total"] == 80
    assert stored[0]["patient_id"] == 1  # the record chosen at Start


@contextmanager
def dashboard_serving(db):
    """The clinician's dashboard (its aiohttp app, as CGAmed serves it) on ``db``, in a thread."""
    import asyncio
    import threading

    from aiohttp import web

    from clarc_sim.hospital.dashboard_app import TestStatus, make_app
    from dsr_graph.web.events import Broadcaster

    port, loop, ready = free_port(), asyncio.new_event_loop(), threading.Event()
    pressed = []
    app = make_app(str(db), TestStatus(), Broadcaster(), lambda *start: pressed.append(start))

    def serve() -> None:
        asyncio.set_event_loop(loop)
        loop.run_until_complete(runner.setup())
        loop.run_until_complete(web.TCPSite(runner, "127.0.0.1", port).start())
        ready.set()
        loop.run_forever()
        loop.run_until_complete(runner.cleanup())

    runner = web.AppRunner(app)
    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    assert ready.wait(20), "the dashboard did not start"
    try:
        yield f"http://127.0.0.1:{port}/", pressed
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(timeout=20)


def test_the_clinician_validates_a_result_once_and_sees_local_times(tmp_path):
    import shutil

    db = tmp_path / "cgamed.sqlite"  # two Barthel results, stored before versions
    shutil.copy(REPO / "test" / "fixtures" / "cgamed_before_versions.sqlite", db)
    with dashboard_serving(db) as (url, _), chromium_page() as page:
        page.goto(url)
        page.wait_for_function("Number(document.body.dataset.results) === 2", timeout=10000)
        page.click("#results tbody tr[data-id='1']")
        page.wait_for_selector("#validation")
        # times in the browser's local time, with the zone (this Chromium runs in UTC)
        assert "Nov 20, 2026" in page.inner_text("#result-detail")
        assert "UTC" in page.inner_text("#result-detail")
        page.click("#validate")  # no name yet
        page.wait_for_function(
            "document.getElementById('validate-error').textContent.includes('name')"
        )
        page.fill("#clinician", "Dr. Ruiz")
        page.click("#validate")
        page.wait_for_function(
            "document.getElementById('validation').textContent.includes('Validated by Dr. Ruiz')",
            timeout=10000,
        )
        assert "validated by Dr. Ruiz" in page.inner_text("#results")
        again = page.evaluate(
            "fetch('/api/results/1/validate', {method: 'POST', headers: {'Content-Type': "
            "'application/json'}, body: JSON.stringify({clinician: 'Dr. Gil'})})"
            ".then(async (r) => [r.status, await r.text()])"
        )
        assert again[0] == 409 and "validated by Dr. Ruiz" in again[1]
        page.reload()  # stored: the page says so when it is opened again
        page.wait_for_function("Number(document.body.dataset.results) === 2", timeout=10000)
        assert "validated by Dr. Ruiz" in page.inner_text("#results")
    [first, second] = stored_tests(db)
    assert first["validated_by"] == "Dr. Ruiz" and first["validated_at"]
    assert second["validated_by"] is None


def mmse_store(db):
    """Two MMSE results of Ana a week apart (the drawings to score) and one of her Barthel
    tests, as CLARC would store them (local_clarc.py runs the tests without ROS)."""
    from clarc_sim.hospital.results_store import ResultsStore

    from local_clarc import Patient, Robot

    store = ResultsStore(db)
    ana = store.add_patient("Ana")["id"]
    for started, answers in (
        ("2026-11-17T10:00:00+00:00", {"recall": [("voice", 1)], "attention": [("voice", 2)]}),
        ("2026-11-24T10:00:00+00:00", {"recall": [("voice", 2)]}),
    ):
        result = Robot(Patient(answers=answers), test="mmse").run_test("Ana")
        finished = started.replace("T10:00", "T10:20")
        store.store(dict(result, started=started, finished=finished, patient_id=ana))
    barthel = Robot().run_test("Ana")
    started, finished = "2026-11-20T09:00:00+00:00", "2026-11-20T09:12:00+00:00"
    store.store(dict(barthel, started=started, finished=finished, patient_id=ana))
    store.close()
    return ana


def test_the_clinician_scores_the_drawings_sees_the_history_and_prints_a_report(tmp_path):
    db = tmp_path / "cgamed.sqlite"
    ana = mmse_store(db)
    with dashboard_serving(db) as (url, pressed), chromium_page() as page:
        page.goto(url)
        page.wait_for_selector("body[data-ready=true]")
        # Start: a patient's record and a test
        page.select_option("#patient-id", str(ana))
        page.select_option("#test", "mmse")
        page.click("#start")
        wait_for(lambda: pressed == [("Ana", "mmse", ana)], 10, "the Start for Ana's record")
        page.wait_for_function("Number(document.body.dataset.results) === 3", timeout=10000)
        page.click("#results tbody tr[data-id='2']")
        page.wait_for_selector("#items")
        # each item with its question and the answer in words
        recall = page.inner_text("#items tr[data-item='recall']")
        assert "What were the three objects?" not in recall  # the question is the item's
        assert "Earlier I named three objects" in recall and "apple, table" in recall
        assert "2/3\tvoice" in recall
        assert page.locator("#items tr[data-item='copying'] svg.drawing path").count() == 1
        assert "To score: writing, copying" in page.inner_text("#validation")
        page.fill("#clinician", "Dr. Ruiz")
        page.click("#validate")  # not while the drawings wait for their scores
        page.wait_for_function(
            "document.getElementById('validate-error').textContent.includes('score writing')"
        )
        page.select_option("#items tr[data-item='writing'] select.score", "1")
        page.click("#items tr[data-item='writing'] .score-button")
        page.wait_for_function(
            "document.querySelector(\"#items tr[data-item='writing']\").innerText.includes('1/1')"
        )
        page.select_option("#items tr[data-item='copying'] select.score", "0")
        page.click("#items tr[data-item='copying'] .score-button")
        page.wait_for_function(
            "document.querySelector(\"#items tr[data-item='copying']\").innerText.includes('0/1')"
        )
        assert "28/30" in page.inner_text("#result-detail h3")
        page.click("#validate")
        page.wait_for_function(
            "document.getElementById('validation').textContent.includes('Validated by Dr. Ruiz')"
        )
        assert page.locator("#items select.score").count() == 0  # it can no longer change
        again = page.evaluate(
            "fetch('/api/results/2/score', {method: 'POST', headers: {'Content-Type': "
            "'application/json'}, body: JSON.stringify({item: 'copying', points: 1, "
            "clinician: 'Dr. Gil'})}).then(async (r) => [r.status, await r.text()])"
        )
        assert again[0] == 409 and "cannot change" in again[1]
        # the history of Ana's MMSE: two points in time, this one marked
        points = page.locator("#history-chart circle.point")
        assert points.count() == 2
        assert "2 tests" in page.inner_text("figure figcaption")
        ys = [float(points.nth(k).get_attribute("cy")) for k in range(2)]
        assert ys[1] < ys[0]  # a better total is higher on the chart
        # the printable report: one page, with the items and the validation
        page.goto(url + "report/2")
        page.wait_for_selector("body[data-ready=true]")
        report = page.inner_text("#report")
        assert "Mini-Mental State Examination" in report and "Ana (record #1)" in report
        assert "Result: 28/30, normal cognition" in report and "Validated by Dr. Ruiz" in report
        assert "Earlier I named three objects" in report and "UTC" in report
        pdf = page.pdf(format="A4")
        assert (
            pdf.count(b"/Type /Page\n") + pdf.count(b"/Type /Page ") + pdf.count(b"/Type /Page/")
            == 1
        ), "the report is one page"
    [first, second, barthel] = stored_tests(db)
    assert second["validated_by"] == "Dr. Ruiz" and second["total"] == 28
    writing = next(i for i in second["items"] if i["item"] == "writing")
    assert writing["points"] == 1 and writing["scored_by"] == "Dr. Ruiz"
    assert first["validated_by"] is None and barthel["test"] == "barthel"
