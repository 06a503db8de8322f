"""The clinician's dashboard (part of the CGAmed stand-in; aiohttp, no ROS): log in, pick a
patient (a record) and a test and press Start, follow the running test, see the results, score
what the clinician scores, validate, follow a patient's history, print a report; an admin
manages the users and reads the audit trail.

Who may do what (clarc_sim/hospital/accounts.py): a technician adds patients and presses Start;
a clinician also scores and validates; an admin manages users and reads the audit trail. Every
request but the login page and the login itself needs a session (an encrypted, HttpOnly,
SameSite=Strict cookie that ends after ``idle`` seconds without a request); every state-changing
request needs the session's CSRF token (``X-CSRF-Token``), a JSON body and this origin; every
request needs an allowed Host (dsr_graph/web/guard.py). ``scored_by`` and ``validated_by`` are
the logged-in user, never a field of the request. Every login (and failed one), Start, score,
validation and change of a user is in the audit trail.

    GET  /login               the login page
    POST /api/login           {"name", "password"}: {"name", "role", "csrf"} (401 wrong name or
                              password, or disabled; 429 after too many failures, Retry-After)
    POST /api/logout          ends the session
    GET  /api/me              {"name", "role", "csrf"} (401 without a session)
    GET  /                    the page (a redirect to /login without a session)
    GET  /report/{id}         a stored test's one-page printable report
    GET  /api/tests           the tests Start offers, each questionnaire with its items
                              (key, title, question, kind, max, needs_clinician, options)
    GET  /api/patients        the patients' records [{"id", "name", "created"}]
    POST /api/patients        {"name": name}: a new record (400 without a name)
    POST /api/start           {"patient_id": id, "test": test}: press Start (400 unknown test,
                              404 no such patient, 409 while a test runs); {"patient": name}
                              starts a Barthel test for a name (as `clarc start` does)
    GET  /api/status          {"running", "patient", "test", "item", "position", "of"}
    GET  /api/results         the stored tests, as `clarc results --json` (with "version" and
                              "scores", every score given)
    GET  /api/results/{id}/audio/{item}/{k}  the k-th clip (from 0) of what was said to an item
                              (audio/wav): only a WAV file inside the robot's clips folder
                              (``clips_dir``), whatever path a result names; 404 otherwise;
                              each listening is in the audit trail
    POST /api/results/{id}/score  {"item", "points"}: score an item that needs the clinician,
                              as the logged-in clinician (400 not such an item or score, 404 no
                              such test, 409 validated already); the result as it is now
    POST /api/results/{id}/validate  {"version": N}: validate the version of the result you saw,
                              once (400 while an item waits for its score, 404 no such test,
                              409 validated already or changed since version N)
    GET  /api/users           the accounts (admin)
    POST /api/users           {"name", "role", "password"}: a new account (admin)
    POST /api/users/{name}/disable, /enable   (admin; you cannot disable yourself)
    GET  /api/audit           the audit trail, newest first (admin)
    GET  /api/events          Server-Sent Events: "status" (the test node), "step" (a step of
                              the test read from the DSR, clarc_agents/course.py), "pelea"
                              (PELEA's errors), "speaker" (what CLARC says), "notification"
                              (what the clinician is told)
"""

from __future__ import annotations

import hmac
import secrets
import time
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

from aiohttp import web
from aiohttp_session import get_session, new_session
from aiohttp_session import setup as setup_sessions
from aiohttp_session.cookie_storage import EncryptedCookieStorage

from clarc_agents import definitions
from clarc_agents.course import TestView, items_in, position, test_name
from clarc_sim.exceptions import (
    AccountError,
    AlreadyValidated,
    InvalidResult,
    ResultChanged,
    UnknownPatient,
    UnknownTest,
)
from clarc_sim.hospital import accounts
from clarc_sim.hospital.result_checks import tests_known
from clarc_sim.hospital.results_store import ResultsStore
from dsr_graph.formats.private_files import write_private
from dsr_graph.web.events import Broadcaster
from dsr_graph.web.guard import LOOPBACK, protect

WEB = Path(str(resources.files("clarc_sim").joinpath("hospital/web")))
PAGE_FILES = (  # all that /static/ serves
    "dashboard.css",
    "dashboard.js",
    "results_view.js",
    "report.css",
    "report.js",
    "login.css",
    "login.js",
)
COOKIE = "cgamed_session"
DEFAULT_IDLE = 900.0  # seconds without a request before a session ends
OPEN_PATHS = ("/login", "/api/login", "/static/login.css", "/static/login.js")
USER = web.RequestKey("user", dict)  # the logged-in user of a request: {"name", "role"}


class TestStatus:
    """What the dashboard shows of the test in progress, read from the DSR's test node (so it is
    right whenever the dashboard starts, and across a restart of PELEA)."""

    __test__ = False  # a clinical test's status, not a pytest class (its tests import it)

    def __init__(self) -> None:
        self.shown: dict[str, Any] = {
            "running": False,
            "patient": "",
            "test": "",
            "item": "",
            "position": 0,
            "of": 0,
        }

    @property
    def running(self) -> bool:
        return bool(self.shown["running"])

    @property
    def patient(self) -> str:
        return str(self.shown["patient"])

    @staticmethod
    def of(test: TestView) -> dict[str, Any]:
        item = test.item if test.running else ""
        return {
            "running": test.running,
            "patient": test.patient,
            "test": test.kind if test.status else "",
            "item": item,
            "position": position(item, test.kind),
            "of": items_in(test.kind),
        }

    def update(self, status: dict[str, Any]) -> None:
        self.shown = dict(status)

    def to_json(self) -> dict[str, Any]:
        return dict(self.shown)


def tests_offered() -> list[dict[str, Any]]:
    """What Start offers: every test, a questionnaire with its items as the clinician reads
    them (the question, the options in words, the maximum)."""
    offered = []
    for test in tests_known():
        if test not in definitions.tests():
            offered.append({"test": test, "title": test_name(test), "items": []})
            continue
        definition = definitions.load(test)
        items = [
            {
                "key": i.key,
                "title": i.title,
                "question": i.question,
                "kind": i.kind,
                "max": i.max,
                "needs_clinician": i.needs_clinician,
                "options": [{"points": o.points, "text": o.text} for o in i.options],
            }
            for i in definition.items
        ]
        bands = [{"name": n, "min": lo, "max": hi} for lo, hi, n in definition.bands]
        offered.append(
            {
                "test": test,
                "title": definition.title,
                "max_total": definition.max_total,
                "bands": bands,
                "items": items,
            }
        )
    return offered


def session_key(db_path: str) -> bytes:
    """The key that encrypts the dashboard's session cookies: 32 random bytes kept beside the
    results store (``<db>.session-key``, 0600), made the first time; a restart of CGAmed keeps
    the sessions. Remove the file to end every session."""
    path = Path(f"{db_path}.session-key")
    try:
        key = path.read_bytes()
        if len(key) == 32:
            return key
    except FileNotFoundError:
        pass
    key = secrets.token_bytes(32)
    write_private(path, key)
    return key


# press_start(patient's name, test, patient's record id or None)
PressStart = Callable[[str, str, "int | None"], None]


def clip_path(folder: str | Path | None, named: str) -> Path | None:
    """The clip a result names, if it is a WAV file inside ``folder`` (symbolic links and ".."
    resolved first): a stored result is not trusted to name any other file."""
    if folder is None or not isinstance(named, str) or not named.endswith(".wav"):
        return None
    root = Path(folder).resolve()
    clip = Path(named).resolve()
    return clip if clip.is_relative_to(root) and clip.is_file() else None


class Dashboard:
    """The dashboard's request handlers (``make_app`` routes them) and what they share: the
    results store, the running test's status, the events, Start and the login throttle."""

    def __init__(
        self,
        db_path: str,
        status: TestStatus,
        events: Broadcaster,
        press_start: PressStart,
        idle: float,
        throttle: accounts.LoginThrottle,
        clips_dir: str | Path | None,
    ):
        self.db_path, self.status, self.events = db_path, status, events
        self.press_start, self.idle, self.throttle = press_start, idle, throttle
        self.clips_dir = clips_dir
        self._db: ResultsStore | None = None

    def db(self) -> ResultsStore:
        if self._db is None:  # this thread's own connection (SQLite connections are per thread)
            self._db = ResultsStore(self.db_path)
        return self._db

    async def body(self, request: web.Request, *keys: str) -> list[Any]:
        try:
            doc = await request.json()
            return [doc[k] for k in keys]
        except (ValueError, KeyError, TypeError):
            fields = ", ".join(f'"{k}": ...' for k in keys)
            raise web.HTTPBadRequest(text=f"send {{{fields}}}") from None

    # ------------------------------------------------------------------ sessions
    @web.middleware
    async def logged_in(self, request: web.Request, handler):
        """A session for everything but the login; the CSRF token for every change."""
        if request.path in OPEN_PATHS:
            return await handler(request)
        session = await get_session(request)
        now = time.time()
        user = session.get("user")
        if user is not None and now - session.get("seen", 0) > self.idle:
            session.invalidate()
            user = None
        account = self.db().user(user["name"]) if user is not None else None
        if account is None or account["disabled"]:  # disabling a user ends their sessions
            if request.path.startswith("/api/"):
                raise web.HTTPUnauthorized(text="log in first (your session ended, or never began)")
            raise web.HTTPFound("/login")
        if request.method in ("POST", "PUT", "PATCH", "DELETE"):
            token = request.headers.get("X-CSRF-Token", "")
            if not hmac.compare_digest(token, session.get("csrf", "")):
                raise web.HTTPForbidden(text="missing or wrong CSRF token (reload the page)")
        session["seen"] = now
        request[USER] = user
        return await handler(request)

    def allowed(self, request: web.Request, action: str) -> dict[str, Any]:
        user = request[USER]
        if not accounts.may(user["role"], action):
            raise web.HTTPForbidden(text=f"a {user['role']} may not {action.replace('_', ' ')}")
        return user

    def audit(
        self, request: web.Request, action: str, test_id: int | None = None, detail=""
    ) -> None:
        self.db().audit(request[USER]["name"], action, test_id, detail)

    async def login_page(self, request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "login.html")

    async def login(self, request: web.Request) -> web.Response:
        name, password = await self.body(request, "name", "password")
        name = str(name)
        keys = [f"name:{name}", f"address:{request.remote}"]
        wait = self.throttle.wait(keys)
        if wait > 0:
            raise web.HTTPTooManyRequests(
                text=f"too many failed logins: try again in {wait:.0f} s",
                headers={"Retry-After": str(int(wait) + 1)},
            )
        account = self.db().user(name)
        outcome = accounts.verify_login(account, password)
        if outcome.user is None:
            self.throttle.failed(keys)
            self.db().audit(name[:100], "login failed", None, f"from {request.remote}")
            raise web.HTTPUnauthorized(text="wrong name or password (or the account is disabled)")
        self.throttle.succeeded(keys[0])
        if outcome.new_hash is not None:
            self.db().set_password(name, outcome.new_hash)
        session = await new_session(request)  # a new session id: no fixation
        csrf = secrets.token_urlsafe(32)
        session.update(user=outcome.user, csrf=csrf, seen=time.time())
        self.db().audit(name, "logged in", None, f"from {request.remote}")
        return web.json_response({**outcome.user, "csrf": csrf})

    async def logout(self, request: web.Request) -> web.Response:
        self.audit(request, "logged out")
        (await get_session(request)).invalidate()
        return web.json_response({"logged_out": True})

    async def me(self, request: web.Request) -> web.Response:
        session = await get_session(request)
        return web.json_response({**request[USER], "csrf": session["csrf"]})

    # ------------------------------------------------------------------ pages
    async def index(self, request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "dashboard.html")

    async def report(self, request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "report.html")

    async def page_file(self, request: web.Request) -> web.FileResponse:
        name = request.match_info["name"]
        if name not in PAGE_FILES:
            raise web.HTTPNotFound()
        return web.FileResponse(WEB / name)

    # ------------------------------------------------------------------ the test
    async def get_tests(self, request: web.Request) -> web.Response:
        return web.json_response(tests_offered())

    async def get_patients(self, request: web.Request) -> web.Response:
        return web.json_response(self.db().patients())

    async def add_patient(self, request: web.Request) -> web.Response:
        self.allowed(request, "add_patient")
        [name] = await self.body(request, "name")
        try:
            patient = self.db().add_patient(str(name))
        except InvalidResult as e:
            raise web.HTTPBadRequest(text=str(e)) from None
        self.audit(request, "added a patient", None, f"record {patient['id']}")
        return web.json_response(patient, status=201)

    async def start(self, request: web.Request) -> web.Response:
        self.allowed(request, "start")
        try:
            doc = await request.json()
            test = str(doc.get("test", "barthel"))
            patient_id = doc.get("patient_id")
            name = str(doc.get("patient", "")).strip()
        except (ValueError, AttributeError):
            raise web.HTTPBadRequest(text='send {"patient_id": <id>, "test": "<test>"}') from None
        if patient_id in (None, "") and not name:
            raise web.HTTPBadRequest(text="choose a patient first")
        if test not in tests_known():
            raise web.HTTPBadRequest(
                text=f"unknown test {test!r}; the tests are {', '.join(tests_known())}"
            )
        if patient_id not in (None, ""):
            try:
                name = self.db().patient(int(patient_id))["name"]
            except (ValueError, TypeError, OverflowError):
                raise web.HTTPBadRequest(
                    text=f"a patient id is a number, got {patient_id!r}"
                ) from None
            except UnknownPatient as e:
                raise web.HTTPNotFound(text=str(e)) from None
            patient_id = int(patient_id)
        else:
            patient_id = None
        if self.status.running:
            raise web.HTTPConflict(text=f"a test with {self.status.patient} is running")
        self.press_start(name, test, patient_id)
        self.audit(request, "started", None, f"{test} for record {patient_id}")
        return web.json_response({"started": name, "test": test, "patient_id": patient_id})

    # ------------------------------------------------------------------ results
    def test_id(self, request: web.Request) -> int:
        try:
            return int(request.match_info["id"])
        except ValueError:
            raise web.HTTPNotFound(text=f"no test {request.match_info['id']!r}") from None

    def clinician_change(self, change: Callable[[], Any]) -> Any:
        """A change the clinician asked of a stored result, as the store answers it: 404 no such
        test, 409 validated already or changed since, 400 anything else wrong."""
        try:
            return change()
        except UnknownTest as e:
            raise web.HTTPNotFound(text=str(e)) from None
        except (AlreadyValidated, ResultChanged) as e:
            raise web.HTTPConflict(text=str(e)) from None
        except InvalidResult as e:
            raise web.HTTPBadRequest(text=str(e)) from None

    async def score(self, request: web.Request) -> web.Response:
        clinician = self.allowed(request, "score")["name"]
        item, points = await self.body(request, "item", "points")
        number = self.test_id(request)
        done = self.clinician_change(lambda: self.db().score(number, str(item), points, clinician))
        self.audit(request, "scored", number, f"{item} = {points} (version {done['version']})")
        return web.json_response(done)

    async def validate(self, request: web.Request) -> web.Response:
        clinician = self.allowed(request, "validate")["name"]
        [version] = await self.body(request, "version")
        if isinstance(version, bool) or not isinstance(version, int):
            raise web.HTTPBadRequest(text="send the version of the result you saw (a number)")
        number = self.test_id(request)
        done = self.clinician_change(lambda: self.db().validate(number, clinician, version=version))
        self.audit(request, "validated", number, f"version {version}")
        return web.json_response(done)

    async def get_status(self, request: web.Request) -> web.Response:
        return web.json_response(self.status.to_json())

    async def get_results(self, request: web.Request) -> web.Response:
        return web.json_response(self.db().tests())

    async def get_audio(self, request: web.Request) -> web.FileResponse:
        number, item = self.test_id(request), request.match_info["item"]
        try:
            k = int(request.match_info["k"])
            entry = next(i for i in self.db().test(number)["items"] if i["item"] == item)
            named = entry.get("audio", [])[k]
        except (UnknownTest, StopIteration, IndexError, ValueError):
            raise web.HTTPNotFound(
                text=f"test {number} has no clip {item}/{request.match_info['k']}"
            ) from None
        clip = clip_path(self.clips_dir, named)
        if clip is None:
            raise web.HTTPNotFound(text="that clip is not in the robot's clips folder") from None
        self.audit(request, "listened", number, f"{item} clip {k}")
        return web.FileResponse(clip, headers={"Content-Type": "audio/wav"})

    # ------------------------------------------------------------------ users, audit
    async def get_users(self, request: web.Request) -> web.Response:
        self.allowed(request, "manage_users")
        return web.json_response(self.db().users())

    async def add_user(self, request: web.Request) -> web.Response:
        self.allowed(request, "manage_users")
        name, role, password = await self.body(request, "name", "role", "password")
        try:
            made = self.db().add_user(str(name), str(role), accounts.hash_password(password))
        except AccountError as e:
            raise web.HTTPBadRequest(text=str(e)) from None
        self.audit(request, "added a user", None, f"{made['name']} ({made['role']})")
        return web.json_response({k: made[k] for k in ("name", "role", "created")}, status=201)

    async def set_user(self, request: web.Request) -> web.Response:
        self.allowed(request, "manage_users")
        name, disable = request.match_info["name"], request.match_info["change"] == "disable"
        if disable and name == request[USER]["name"]:
            raise web.HTTPBadRequest(text="you cannot disable yourself")
        try:
            self.db().set_disabled(name, disable)
        except AccountError as e:
            raise web.HTTPNotFound(text=str(e)) from None
        self.audit(request, "disabled a user" if disable else "enabled a user", None, name)
        return web.json_response({"name": name, "disabled": disable})

    async def get_audit(self, request: web.Request) -> web.Response:
        self.allowed(request, "read_audit")
        return web.json_response(self.db().audit_trail())

    async def stream(self, request: web.Request) -> web.StreamResponse:
        return await self.events.stream(request, first=lambda: [("status", self.status.to_json())])

    async def close(self, app: web.Application) -> None:
        if self._db is not None:
            self._db.close()


def make_app(
    db_path: str,
    status: TestStatus,
    events: Broadcaster,
    press_start: PressStart,
    secret_key: bytes,
    hosts: frozenset[str] = LOOPBACK,
    idle: float = DEFAULT_IDLE,
    throttle: accounts.LoginThrottle | None = None,
    clips_dir: str | Path | None = None,
) -> web.Application:
    """``secret_key``: 32 bytes that encrypt the session cookies (CGAmed keeps it in a file, so
    a restart keeps everyone logged in). ``clips_dir``: the only folder whose clips are played
    (None: none is)."""
    dashboard = Dashboard(
        db_path, status, events, press_start, idle, throttle or accounts.LoginThrottle(), clips_dir
    )
    app = web.Application(client_max_size=64 * 1024)  # no request of ours is larger
    protect(app, hosts)
    storage = EncryptedCookieStorage(
        secret_key,
        cookie_name=COOKIE,
        httponly=True,
        samesite="Strict",
        max_age=int(idle),  # the cookie (and its encrypted stamp) ends with the idle time
    )
    setup_sessions(app, storage)
    app.middlewares.append(dashboard.logged_in)
    app.router.add_get("/login", dashboard.login_page)
    app.router.add_post("/api/login", dashboard.login)
    app.router.add_post("/api/logout", dashboard.logout)
    app.router.add_get("/api/me", dashboard.me)
    app.router.add_get("/", dashboard.index)
    app.router.add_get("/report/{id}", dashboard.report)
    app.router.add_get("/static/{name}", dashboard.page_file)
    app.router.add_get("/api/tests", dashboard.get_tests)
    app.router.add_get("/api/patients", dashboard.get_patients)
    app.router.add_post("/api/patients", dashboard.add_patient)
    app.router.add_post("/api/start", dashboard.start)
    app.router.add_get("/api/status", dashboard.get_status)
    app.router.add_get("/api/results", dashboard.get_results)
    app.router.add_get("/api/results/{id}/audio/{item}/{k}", dashboard.get_audio)
    app.router.add_post("/api/results/{id}/score", dashboard.score)
    app.router.add_post("/api/results/{id}/validate", dashboard.validate)
    app.router.add_get("/api/users", dashboard.get_users)
    app.router.add_post("/api/users", dashboard.add_user)
    app.router.add_post(r"/api/users/{name}/{change:disable|enable}", dashboard.set_user)
    app.router.add_get("/api/audit", dashboard.get_audit)
    app.router.add_get("/api/events", dashboard.stream)
    app.on_cleanup.append(dashboard.close)
    return app
