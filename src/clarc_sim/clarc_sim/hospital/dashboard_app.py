"""The clinician's dashboard (part of the CGAmed stand-in; aiohttp, no ROS): pick a patient and
press Start, follow the running test, see the results and the history from the results store.

    GET  /                    the page
    POST /api/start           {"patient": name}: press Start (409 while a test runs)
    GET  /api/status          {"running", "patient", "item", "position"}
    GET  /api/results         the stored tests, as `clarc results --json`
    POST /api/results/{id}/validate  {"clinician": name}: validate a stored result, once
                              (400 without a name, 404 no such test, 409 validated already)
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

from clarc_agents.course import TestView, position
from clarc_agents.exceptions import AlreadyValidated, InvalidResult, UnknownTest
from clarc_sim.hospital.results_store import ResultsStore
from dsr_graph.web.events import Broadcaster

WEB = Path(str(resources.files("clarc_sim").joinpath("hospital/web")))


class TestStatus:
    """What the dashboard shows of the test in progress, read from the DSR's test node (so it is
    right whenever the dashboard starts, and across a restart of PELEA)."""

    def __init__(self) -> None:
        self.running = False
        self.patient = ""
        self.item = ""
        self.position = 0

    @staticmethod
    def of(test: TestView) -> dict[str, Any]:
        item = test.item if test.running else ""
        return {
            "running": test.running,
            "patient": test.patient,
            "item": item,
            "position": position(item),
        }

    def update(self, status: dict[str, Any]) -> None:
        self.running, self.patient = status["running"], status["patient"]
        self.item, self.position = status["item"], status["position"]

    def to_json(self) -> dict[str, Any]:
        return {
            "running": self.running,
            "patient": self.patient,
            "item": self.item,
            "position": self.position,
        }


def make_app(
    db_path: str, status: TestStatus, events: Broadcaster, press_start: Callable[[str], None]
) -> web.Application:
    store: dict[str, ResultsStore] = {}

    def results() -> list:
        if "db" not in store:  # this thread's own connection (SQLite connections are per thread)
            store["db"] = ResultsStore(db_path)
        return store["db"].tests()

    async def index(request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "dashboard.html")

    async def start(request: web.Request) -> web.Response:
        try:
            patient = str((await request.json())["patient"]).strip()
        except (ValueError, KeyError, TypeError):
            raise web.HTTPBadRequest(text='send {"patient": "<name>"}') from None
        if not patient:
            raise web.HTTPBadRequest(text="choose a patient first")
        if status.running:
            raise web.HTTPConflict(text=f"a test with {status.patient} is running")
        press_start(patient)
        return web.json_response({"started": patient})

    async def get_status(request: web.Request) -> web.Response:
        return web.json_response(status.to_json())

    async def get_results(request: web.Request) -> web.Response:
        return web.json_response(results())

    async def validate(request: web.Request) -> web.Response:
        try:
            test_id = int(request.match_info["id"])
            clinician = str((await request.json())["clinician"])
        except (ValueError, KeyError, TypeError):
            raise web.HTTPBadRequest(text='send {"clinician": "<name>"}') from None
        results()  # this thread's connection
        try:
            return web.json_response(store["db"].validate(test_id, clinician))
        except UnknownTest as e:
            raise web.HTTPNotFound(text=str(e)) from None
        except AlreadyValidated as e:
            raise web.HTTPConflict(text=str(e)) from None
        except InvalidResult as e:
            raise web.HTTPBadRequest(text=str(e)) from None

    async def stream(request: web.Request) -> web.StreamResponse:
        return await events.stream(request, first=lambda: [("status", status.to_json())])

    async def close(app: web.Application) -> None:
        if "db" in store:
            store["db"].close()

    app = web.Application()
    app.router.add_get("/", index)
    app.router.add_static("/static/", WEB, show_index=False)
    app.router.add_post("/api/start", start)
    app.router.add_get("/api/status", get_status)
    app.router.add_get("/api/results", get_results)
    app.router.add_post("/api/results/{id}/validate", validate)
    app.router.add_get("/api/events", stream)
    app.on_cleanup.append(close)
    return app
