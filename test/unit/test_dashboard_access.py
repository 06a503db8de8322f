"""Who may do what on the clinician's dashboard, through its HTTP API (aiohttp's test client,
no browser, no ROS): logging in, sessions, CSRF, roles, the Host and Origin checks, the
headers, the audit trail, and what the pages' folder serves."""

import asyncio
import json

import pytest
from aiohttp.test_utils import TestClient, TestServer

from clarc_sim.hospital import accounts
from clarc_sim.hospital.dashboard_app import TestStatus, make_app
from clarc_sim.hospital.results_store import ResultsStore
from dsr_graph.web.events import Broadcaster

PASSWORD = "a long enough passphrase"


def mmse_result():
    from local_clarc import Robot

    return Robot(test="mmse").run_test("Ana")


@pytest.fixture(scope="module")
def mmse():
    return mmse_result()


@pytest.fixture
def db(tmp_path, mmse):
    path = tmp_path / "cgamed.sqlite"
    store = ResultsStore(path)
    for name, role in (("tess", "technician"), ("clara", "clinician"), ("ada", "admin")):
        store.add_user(name, role, accounts.hash_password(PASSWORD))
    store.add_patient("Ana")
    store.store(mmse)
    store.close()
    return path


def run(db, scenario, **app_options):
    """``scenario(client, pressed)`` against the dashboard on ``db``."""
    pressed = []

    async def main():
        app = make_app(
            str(db),
            TestStatus(),
            Broadcaster(),
            lambda *start: pressed.append(start),
            secret_key=b"k" * 32,
            **app_options,
        )
        async with TestClient(TestServer(app)) as client:
            await scenario(client, pressed)

    asyncio.run(main())
    return pressed


async def log_in(client, name, password=PASSWORD):
    r = await client.post("/api/login", json={"name": name, "password": password})
    assert r.status == 200, await r.text()
    return (await r.json())["csrf"]


def post(client, url, doc, csrf, **headers):
    return client.post(url, json=doc, headers={"X-CSRF-Token": csrf, **headers})


def test_nothing_but_the_login_without_a_session(db):
    async def scenario(client, pressed):
        for url in ("/api/results", "/api/patients", "/api/me", "/api/audit", "/api/events"):
            assert (await client.get(url)).status == 401, url
        page = await client.get("/", allow_redirects=False)
        assert page.status == 302 and page.headers["Location"] == "/login"
        assert (await client.get("/login")).status == 200
        r = await client.post("/api/start", json={"patient_id": 1, "test": "mmse"})
        assert r.status == 401

    assert run(db, scenario) == []


def test_a_login_is_checked_and_throttled_and_every_try_is_audited(db):
    async def scenario(client, pressed):
        for _ in range(5):
            r = await client.post("/api/login", json={"name": "clara", "password": "wrong one!"})
            assert r.status == 401 and "wrong name or password" in await r.text()
        r = await client.post("/api/login", json={"name": "clara", "password": PASSWORD})
        assert r.status == 429 and int(r.headers["Retry-After"]) >= 1
        nobody = await client.post("/api/login", json={"name": "nobody", "password": PASSWORD})
        assert nobody.status == 429  # the address is throttled too

    run(db, scenario)
    trail = ResultsStore(db).audit_trail()
    assert [a["action"] for a in trail].count("login failed") == 5


def test_a_disabled_user_cannot_log_in_and_loses_the_session(db):
    async def scenario(client, pressed):
        csrf = await log_in(client, "tess")
        ResultsStore(db).set_disabled("tess")
        assert (await client.get("/api/results")).status == 401
        r = await client.post("/api/login", json={"name": "tess", "password": PASSWORD})
        assert r.status == 401
        del csrf

    run(db, scenario)


def test_a_change_needs_the_session_s_csrf_token_json_and_this_origin(db):
    async def scenario(client, pressed):
        csrf = await log_in(client, "tess")
        start = {"patient_id": 1, "test": "mmse"}
        assert (await client.post("/api/start", json=start)).status == 403  # no token
        r = await post(client, "/api/start", start, "not the token")
        assert r.status == 403 and "CSRF" in await r.text()
        r = await client.post(
            "/api/start",
            data=json.dumps(start),
            headers={"X-CSRF-Token": csrf, "Content-Type": "text/plain"},
        )
        assert r.status == 415
        r = await post(client, "/api/start", start, csrf, Origin="http://evil.example")
        assert r.status == 403 and "another origin" in await r.text()
        r = await post(client, "/api/start", start, csrf, **{"Sec-Fetch-Site": "cross-site"})
        assert r.status == 403
        assert pressed == []
        r = await post(client, "/api/start", start, csrf, Origin=str(client.make_url("/"))[:-1])
        assert r.status == 200, await r.text()
        assert pressed == [("Ana", "mmse", 1)]

    run(db, scenario)


def test_a_wrong_host_gets_nothing(db):
    async def scenario(client, pressed):
        for url in ("/login", "/", "/api/results", "/static/login.js"):
            r = await client.get(url, headers={"Host": "rebound.example:8081"})
            assert r.status == 403, url
        r = await client.get("/login", headers={"Host": "cgamed.ward3:8081"})
        assert r.status == 200  # configured

    run(db, scenario, hosts=frozenset({"127.0.0.1", "localhost", "::1", "cgamed.ward3"}))


def test_roles_and_who_scores_and_validates_comes_from_the_session(db):
    async def scenario(client, pressed):
        csrf = await log_in(client, "tess")  # a technician: patients and Start only
        r = await post(client, "/api/patients", {"name": "Luis"}, csrf)
        assert r.status == 201
        r = await post(client, "/api/results/1/score", {"item": "writing", "points": 1}, csrf)
        assert r.status == 403 and "technician may not score" in await r.text()
        assert (await post(client, "/api/results/1/validate", {"version": 1}, csrf)).status == 403
        assert (await client.get("/api/users")).status == 403
        await post(client, "/api/logout", {}, csrf)
        assert (await client.get("/api/results")).status == 401

        csrf = await log_in(client, "clara")
        score = {"item": "writing", "points": 1, "clinician": "Dr. Anyone"}
        r = await post(client, "/api/results/1/score", score, csrf)
        assert r.status == 200, await r.text()
        assert (await r.json())["version"] == 2
        r = await post(client, "/api/results/1/score", dict(score, points=0), csrf)  # re-score
        assert (await r.json())["version"] == 3
        r = await post(client, "/api/results/1/score", {"item": "copying", "points": 0}, csrf)
        seen = (await r.json())["version"]
        r = await post(client, "/api/results/1/validate", {"version": seen - 1}, csrf)
        assert r.status == 409 and "changed since you saw it" in await r.text()
        r = await post(client, "/api/results/1/validate", {"version": seen, "clinician": "X"}, csrf)
        assert r.status == 200 and (await r.json())["validated_by"] == "clara"
        r = await post(client, "/api/results/1/validate", {"version": seen}, csrf)
        assert r.status == 409
        await post(client, "/api/logout", {}, csrf)

        csrf = await log_in(client, "ada")  # an admin: users and the audit trail
        r = await post(client, "/api/start", {"patient_id": 1, "test": "mmse"}, csrf)
        assert r.status == 403
        new = {"name": "tom", "role": "technician", "password": "short"}
        assert (await post(client, "/api/users", new, csrf)).status == 400
        new["password"] = PASSWORD
        assert (await post(client, "/api/users", new, csrf)).status == 201
        assert (await post(client, "/api/users/ada/disable", {}, csrf)).status == 400
        assert (await post(client, "/api/users/tom/disable", {}, csrf)).status == 200
        trail = await (await client.get("/api/audit")).json()
        actions = [(a["user"], a["action"]) for a in reversed(trail)]
        assert ("clara", "validated") in actions and ("ada", "added a user") in actions
        assert actions.count(("clara", "scored")) == 3

    run(db, scenario)
    [result] = ResultsStore(db).tests()
    writing = next(i for i in result["items"] if i["item"] == "writing")
    assert writing["points"] == 0 and writing["scored_by"] == "clara"
    kept = [(s["item"], s["points"]) for s in result["scores"]]
    assert kept == [("writing", 1), ("writing", 0), ("copying", 0)]  # the earlier score kept
    assert result["validated_by"] == "clara"


def test_every_answer_carries_the_protective_headers_and_only_page_files_are_served(db):
    async def scenario(client, pressed):
        login = await client.get("/login")
        csp = login.headers["Content-Security-Policy"]
        assert "default-src 'self'" in csp and "frame-ancestors 'none'" in csp
        assert login.headers["X-Content-Type-Options"] == "nosniff"
        assert login.headers["Referrer-Policy"] == "no-referrer"
        await log_in(client, "clara")
        for name in ("dashboard_app.py", "../results_store.py", "accounts.py", "%2e%2e%2f"):
            assert (await client.get(f"/static/{name}")).status == 404, name
        assert (await client.get("/static/dashboard.js")).status == 200
        assert (await client.get("/api/results")).headers["Cache-Control"] == "no-store"

    run(db, scenario)


def test_the_audit_trail_cannot_be_changed(db):
    import sqlite3

    store = ResultsStore(db)
    store.audit("clara", "validated", 1)
    with pytest.raises(sqlite3.DatabaseError, match="append-only"):
        store.db.execute("UPDATE audit SET user = 'someone else'")
    with pytest.raises(sqlite3.DatabaseError, match="append-only"):
        store.db.execute("DELETE FROM audit")


def test_a_session_ends_after_its_idle_time(db):
    async def scenario(client, pressed):
        await log_in(client, "clara")
        assert (await client.get("/api/me")).status == 200
        await asyncio.sleep(1.5)
        assert (await client.get("/api/me")).status == 401

    run(db, scenario, idle=1.0)


def test_a_clip_is_played_only_from_the_robot_s_clips_folder_and_audited(tmp_path):
    """What the patient said is the clinician's evidence for an item the robot could not
    understand; the path a stored result names is not trusted to reach any other file."""
    import wave

    from local_clarc import Patient, Robot

    clips = tmp_path / "clips"
    clips.mkdir()
    with wave.open(str(clips / "recall-1.wav"), "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(16000)
        w.writeframes(bytes(3200))
    secret = tmp_path / "secret.wav"
    secret.write_bytes(b"RIFF not for the dashboard")
    result = Robot(Patient(answers={"recall": ["garbled", "garbled"]}), test="mmse").run_test()
    recall = next(i for i in result["items"] if i["item"] == "recall")
    recall["audio"] = [str(clips / "recall-1.wav"), str(clips / ".." / "secret.wav")]
    path = tmp_path / "cgamed.sqlite"
    store = ResultsStore(path)
    store.add_user("clara", "clinician", accounts.hash_password(PASSWORD))
    test_id = store.store(result)
    store.close()

    async def scenario(client, pressed):
        url = f"/api/results/{test_id}/audio/recall"
        assert (await client.get(f"{url}/0")).status == 401  # a session first
        await log_in(client, "clara")
        played = await client.get(f"{url}/0")
        assert played.status == 200 and played.headers["Content-Type"] == "audio/wav"
        assert (await played.read())[:4] == b"RIFF"
        for k in ("1", "2", "x"):  # outside the folder, no such clip, not a number
            assert (await client.get(f"{url}/{k}")).status == 404, k
        assert (await client.get(f"/api/results/{test_id}/audio/naming/0")).status == 404
        results = await (await client.get("/api/results")).json()
        listed = next(i for i in results[0]["items"] if i["item"] == "recall")
        assert listed["needs_clinician"] and results[0]["provisional"]

    run(path, scenario, clips_dir=clips)
    trail = ResultsStore(path).audit_trail()
    assert [a["detail"] for a in trail if a["action"] == "listened"] == ["recall clip 0"]
