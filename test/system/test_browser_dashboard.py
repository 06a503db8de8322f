"""The clinician's dashboard in a real browser (headless Chromium + Playwright): a test started
and shown complete, a result validated and scored, the history and a report, and who may do
what (a login, roles, another origin's page, a wrong Host). The viewer is test_browser.py."""

import os
import subprocess
from contextlib import contextmanager
from pathlib import Path

from browser import chromium_page, free_port, http_get
from ros_processes import (
    fresh_domain_id,
    stored_tests,
    wait_for,
)

REPO = Path(__file__).resolve().parents[2]
PASSWORD = "a long enough passphrase"


def add_user(db, name, role, env=None):
    """``clarc user add`` as a script does it: the password twice on stdin."""
    subprocess.run(
        ["clarc", "user", "add", name, "--role", role, "--db", str(db)],
        input=f"{PASSWORD}\n{PASSWORD}\n",
        text=True,
        check=True,
        timeout=60,
        env=env,
    )


def log_in(page, url, name, password=PASSWORD):
    page.goto(url + "login")
    page.fill("#name", name)
    page.fill("#password", password)
    page.click("#log-in")
    page.wait_for_selector("body[data-ready=true]", timeout=15000)


def test_dashboard_starts_a_test_and_shows_it_complete(tmp_path):
    db = tmp_path / "cgamed.sqlite"
    port = free_port()
    env = dict(os.environ, ROS_DOMAIN_ID=str(fresh_domain_id()))
    add_user(db, "Dr. Ruiz", "clinician", env)
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

        # launch.sh starts fifteen Python processes as CGAmed starts: half a minute of CPU and
        # more, which a machine whose cores are busy with other work gives slowly (seen: > 60 s)
        wait_for(lambda: http_get(url + "login")[0] == 200, 150, "the dashboard")
        with chromium_page() as page:
            log_in(page, url, "Dr. Ruiz")
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

    from clarc_sim.hospital import accounts
    from clarc_sim.hospital.dashboard_app import TestStatus, make_app
    from clarc_sim.hospital.results_store import ResultsStore
    from dsr_graph.web.events import Broadcaster

    store = ResultsStore(db)
    for name, role in (("Dr. Ruiz", "clinician"), ("Tess", "technician")):
        store.add_user(name, role, accounts.hash_password(PASSWORD))
    store.close()
    port, loop, ready = free_port(), asyncio.new_event_loop(), threading.Event()
    pressed = []
    app = make_app(
        str(db),
        TestStatus(),
        Broadcaster(),
        lambda *start: pressed.append(start),
        secret_key=b"s" * 32,
    )

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
        log_in(page, url, "Dr. Ruiz")
        page.wait_for_function("Number(document.body.dataset.results) === 2", timeout=10000)
        page.click("#results tbody tr[data-id='1']")
        page.wait_for_selector("#validation")
        # times in the browser's local time, with the zone (this Chromium runs in UTC)
        assert "Nov 20, 2026" in page.inner_text("#result-detail")
        assert "UTC" in page.inner_text("#result-detail")
        assert page.inner_text("#validate") == "Validate as Dr. Ruiz"  # the logged-in user
        page.click("#validate")
        page.wait_for_function(
            "document.getElementById('validation').textContent.includes('Validated by Dr. Ruiz')",
            timeout=10000,
        )
        assert "validated by Dr. Ruiz" in page.inner_text("#results")
        again = page.evaluate(SAME_ORIGIN_POST, ["/api/results/1/validate", {"version": 1}])
        assert again[0] == 409 and "validated by Dr. Ruiz" in again[1]
        page.reload()  # stored: the page says so when it is opened again
        page.wait_for_function("Number(document.body.dataset.results) === 2", timeout=10000)
        assert "validated by Dr. Ruiz" in page.inner_text("#results")
    [first, second] = stored_tests(db)
    assert first["validated_by"] == "Dr. Ruiz" and first["validated_at"]
    assert second["validated_by"] is None


# a POST as the dashboard's own page sends it (its CSRF token from /api/me)
SAME_ORIGIN_POST = """async ([url, doc]) => {
  const me = await (await fetch('/api/me')).json();
  const r = await fetch(url, {method: 'POST', body: JSON.stringify(doc),
    headers: {'Content-Type': 'application/json', 'X-CSRF-Token': me.csrf}});
  return [r.status, await r.text()];
}"""


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
        log_in(page, url, "Dr. Ruiz")
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
            SAME_ORIGIN_POST, ["/api/results/2/score", {"item": "copying", "points": 1}]
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


ATTACKER_PAGE = """<!doctype html><html><body>
<form id="f" method="POST" enctype="text/plain" action="{dashboard}api/results/1/validate">
<input name='{{"version": 1, "x": "' value='"}}'><input id="go" type="submit"></form>
<script>
const dashboard = "{dashboard}";
async function attack() {{
  const out = [];
  for (const [url, doc] of [["api/start", {{patient_id: 1, test: "mmse"}}],
                            ["api/results/1/score", {{item: "writing", points: 1}}],
                            ["api/results/1/validate", {{version: 1}}]]) {{
    for (const type of ["text/plain", "application/json"]) {{
      try {{
        const r = await fetch(dashboard + url, {{method: "POST", credentials: "include",
          mode: type === "text/plain" ? "no-cors" : "cors",
          headers: {{"Content-Type": type}}, body: JSON.stringify(doc)}});
        out.push(url + " " + type + " " + r.type + " " + r.status);
      }} catch (e) {{ out.push(url + " " + type + " blocked"); }}
    }}
  }}
  document.body.dataset.done = out.join("; ");
}}
attack();
</script></body></html>"""


@contextmanager
def page_server(html):
    """Another origin (this machine, another port) serving one page."""
    import http.server
    import threading

    class Page(http.server.BaseHTTPRequestHandler):
        def do_GET(self):
            body = html.encode()
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", free_port()), Page)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        thread.join(timeout=10)


def test_a_page_of_another_origin_cannot_start_score_or_validate(tmp_path):
    db = tmp_path / "cgamed.sqlite"
    mmse_store(db)
    with dashboard_serving(db) as (url, pressed), chromium_page(csp=True) as page:
        log_in(page, url, "Dr. Ruiz")  # the clinician is logged in, in this very browser
        assert page.refused == []  # the dashboard works under its own CSP
        before = stored_tests(db)
        # the same site (127.0.0.1), another port: the session cookie is even sent along
        with page_server(ATTACKER_PAGE.format(dashboard=url)) as evil:
            page.goto(evil)
            page.wait_for_selector("body[data-done]", timeout=15000)
            tried = page.get_attribute("body", "data-done")
            # none answered in a way the page can read (a "simple" POST reaches the server,
            # whose refusal the browser keeps from the page; a JSON one fails its preflight)
            assert all(t.endswith(("blocked", "opaque 0")) for t in tried.split("; ")), tried
            with page.expect_navigation():
                page.click("#go")  # a cross-site form POST, as text/plain "JSON"
            assert "send JSON" in page.content() or "another origin" in page.content()
        assert pressed == []
        assert stored_tests(db) == before  # nothing scored, nothing validated
        # nor can it show the dashboard in a frame (clickjacking)
        with page_server(f'<iframe id="f" src="{url}"></iframe>') as framing:
            page.goto(framing)
            page.wait_for_timeout(1000)
            frame = page.frame_locator("#f")
            assert frame.locator("#start").count() == 0
    actions = {a["action"] for a in audit_trail_of(db)}
    assert not actions & {"started", "scored", "validated"}


def audit_trail_of(db):
    from clarc_sim.hospital.results_store import ResultsStore

    store = ResultsStore(db)
    try:
        return store.audit_trail()
    finally:
        store.close()


def test_a_wrong_host_gets_nothing_from_the_dashboard(tmp_path):
    db = tmp_path / "cgamed.sqlite"
    with dashboard_serving(db) as (url, _):
        rebound = url.replace("127.0.0.1", "rebind.example")
        with chromium_page(resolve={"rebind.example": "127.0.0.1"}) as page:
            for path in ("login", "", "api/results", "api/patients"):
                assert page.goto(rebound + path).status == 403, path
