"""The clinician's dashboard (part of the CGAmed stand-in; aiohttp, no ROS): pick a patient (a
record) and a test and press Start, follow the running test, see the results, score what the
clinician scores, validate, follow a patient's history, print a report.

    GET  /                    the page
    GET  /report/{id}         a stored test's one-page printable report
    GET  /api/tests           the tests Start offers, each questionnaire with its items
                              (key, title, question, kind, max, needs_clinician, options)
    GET  /api/patients        the patients' records [{"id", "name", "created"}]
    POST /api/patients        {"name": name}: a new record (400 without a name)
    POST /api/start           {"patient_id": id, "test": test}: press Start (400 unknown test,
                              404 no such patient, 409 while a test runs); {"patient": name}
                              starts a Barthel test for a name (as `clarc start` does)
    GET  /api/status          {"running", "patient", "test", "item", "position", "of"}
    GET  /api/results         the stored tests, as `clarc results --json`
    POST /api/results/{id}/score  {"item", "points", "clinician"}: score an item that needs the
                              clinician (400 not such an item or score, 404 no such test,
                              409 validated already); the result as it is now
    POST /api/results/{id}/validate  {"clinician": name}: validate a stored result, once
                              (400 without a name or while an item waits for its score, 404 no
                              such test, 409 validated already)
    GET  /api/events          Server-Sent Events: "status" (the test node), "step" (a step of
                              the test read from the DSR, clarc_agents/course.py), "pelea"
                              (PELEA's errors), "speaker" (what CLARC says), "notification"
                              (what the clinician is told)
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

from aiohttp import web

from clarc_agents import definitions
from clarc_agents.course import TestView, items_in, position, test_name
from clarc_agents.exceptions import AlreadyValidated, InvalidResult, UnknownPatient, UnknownTest
from clarc_sim.hospital.results_store import ResultsStore, tests_known
from dsr_graph.web.events import Broadcaster

WEB = Path(str(resources.files("clarc_sim").joinpath("hospital/web")))


class TestStatus:
    """What the dashboard shows of the test in progress, read from the DSR's test node (so it is
    right whenever the dashboard starts, and across a restart of PELEA)."""

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


# press_start(patient's name, test, patient's record id or None)
PressStart = Callable[[str, str, "int | None"], None]


def make_app(
    db_path: str, status: TestStatus, events: Broadcaster, press_start: PressStart
) -> web.Application:
    store: dict[str, ResultsStore] = {}

    def db() -> ResultsStore:
        if "db" not in store:  # this thread's own connection (SQLite connections are per thread)
            store["db"] = ResultsStore(db_path)
        return store["db"]

    def results() -> list:
        return db().tests()

    async def body(request: web.Request, *keys: str) -> list[Any]:
        try:
            doc = await request.json()
            return [doc[k] for k in keys]
        except (ValueError, KeyError, TypeError):
            fields = ", ".join(f'"{k}": ...' for k in keys)
            raise web.HTTPBadRequest(text=f"send {{{fields}}}") from None

    async def index(request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "dashboard.html")

    async def report(request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "report.html")

    async def get_tests(request: web.Request) -> web.Response:
        return web.json_response(tests_offered())

    async def get_patients(request: web.Request) -> web.Response:
        return web.json_response(db().patients())

    async def add_patient(request: web.Request) -> web.Response:
        [name] = await body(request, "name")
        try:
            return web.json_response(db().add_patient(str(name)), status=201)
        except InvalidResult as e:
            raise web.HTTPBadRequest(text=str(e)) from None

    async def start(request: web.Request) -> web.Response:
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
                name = db().patient(int(patient_id))["name"]
            except (ValueError, TypeError):
                raise web.HTTPBadRequest(
                    text=f"a patient id is a number, got {patient_id!r}"
                ) from None
            except UnknownPatient as e:
                raise web.HTTPNotFound(text=str(e)) from None
            patient_id = int(patient_id)
        else:
            patient_id = None
        if status.running:
            raise web.HTTPConflict(text=f"a test with {status.patient} is running")
        press_start(name, test, patient_id)
        return web.json_response({"started": name, "test": test, "patient_id": patient_id})

    def test_id(request: web.Request) -> int:
        try:
            return int(request.match_info["id"])
        except ValueError:
            raise web.HTTPNotFound(text=f"no test {request.match_info['id']!r}") from None

    def clinician_change(change: Callable[[], Any]) -> web.Response:
        """A change the clinician asked of a stored result, as the store answers it: 404 no such
        test, 409 validated already, 400 anything else wrong."""
        try:
            return web.json_response(change())
        except UnknownTest as e:
            raise web.HTTPNotFound(text=str(e)) from None
        except AlreadyValidated as e:
            raise web.HTTPConflict(text=str(e)) from None
        except InvalidResult as e:
            raise web.HTTPBadRequest(text=str(e)) from None

    async def score(request: web.Request) -> web.Response:
        item, points, clinician = await body(request, "item", "points", "clinician")
        number = test_id(request)
        return clinician_change(lambda: db().score(number, str(item), points, str(clinician)))

    async def get_status(request: web.Request) -> web.Response:
        return web.json_response(status.to_json())

    async def get_results(request: web.Request) -> web.Response:
        return web.json_response(results())

    async def validate(request: web.Request) -> web.Response:
        [clinician] = await body(request, "clinician")
        number = test_id(request)
        return clinician_change(lambda: db().validate(number, str(clinician)))

    async def stream(request: web.Request) -> web.StreamResponse:
        return await events.stream(request, first=lambda: [("status", status.to_json())])

    async def close(app: web.Application) -> None:
        if "db" in store:
            store["db"].close()

    app = web.Application()
    app.router.add_get("/", index)
    app.router.add_get("/report/{id}", report)
    app.router.add_static("/static/", WEB, show_index=False)
    app.router.add_get("/api/tests", get_tests)
    app.router.add_get("/api/patients", get_patients)
    app.router.add_post("/api/patients", add_patient)
    app.router.add_post("/api/start", start)
    app.router.add_get("/api/status", get_status)
    app.router.add_get("/api/results", get_results)
    app.router.add_post("/api/results/{id}/score", score)
    app.router.add_post("/api/results/{id}/validate", validate)
    app.router.add_get("/api/events", stream)
    app.on_cleanup.append(close)
    return app
