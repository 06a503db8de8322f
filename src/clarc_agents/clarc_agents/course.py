"""The course of a test as the DSR tells it (pure): the steps the launch's monitor prints and the
clinician's dashboard logs, found by comparing what the graph says of the test before and after
each change. Observers read only the DSR (the paper: it "practically provides a semantically
annotated view of the scene"), so they stay right across a restart of PELEA or of themselves,
and a resynchronisation never repeats a step.

    course = Course(since=datetime.now(UTC))
    for event in course.follow(graph):   # after every change of the replica
        ...                              # {"event": "answer", "item": "feeding", ...}

A test the observer finds under way is told from its start if it started at or after ``since``
(it is the one the observer was started for), otherwise as "following" from where it is.

Events (``event`` and its fields): following (patient, item, position: a test already running
when the observer started), start_requested (patient), started (patient), item (item, position),
listening (item, attempt), answer (item, points, via), no_answer (item, attempt),
not_understood (item, heard, attempt), unsure (item, heard, attempt: an option heard not for
sure, being confirmed), skip (item), window_interrupted (item, attempt),
unanswered (item), person_lost, person_back, clinician_called (unanswered), finished (result).
A Get Up & Go test (``started`` says ``test``) has instead: trial (trial), phase (trial, phase),
timed (trial, tug_seconds, band), trial_void (trial), and finished (result: the stored result, or
``{"test", "patient", "timed": false, "void_reasons"}`` when no trial could be timed).
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from clarc_agents import definitions
from clarc_agents.definitions import Definition
from clarc_agents.gug.record import GugRecord, gait, result
from clarc_agents.questionnaire.low_to_high import record
from clarc_agents.questionnaire.record import ItemResult
from clarc_agents.test_node import person_present
from dsr_graph.model.graph import Graph

TIMED = "get_up_and_go"  # the test that is timed, not a questionnaire


@dataclass(frozen=True)
class TestView:
    status: str = ""
    patient: str = ""
    started: str = ""
    requested: str = ""  # the patient a pending Start is for
    item: str = ""
    items: tuple[tuple[str, ItemResult], ...] = ()  # as PELEA's record reads them
    person_present: bool = False
    clinician_called: bool = False
    kind: str = "barthel"
    gait: tuple[tuple[str, Any], ...] = ()  # the gait node's trial, status, phase, ... (GUG)

    @property
    def running(self) -> bool:
        return self.status == "running"

    def of(self, item: str) -> ItemResult:
        return dict(self.items).get(item, ItemResult(item))


def view(graph: Graph) -> TestView:
    """What the DSR says of the test: its node, and its items as PELEA's record reads them."""
    test = graph.find("test")
    if test is None:
        return TestView()
    t = test.attrs
    kind = str(t.get("kind", "barthel"))
    rec = record(graph, _definition(kind))
    return TestView(
        status=str(t.get("status", "")),
        patient=rec.patient,
        started=rec.started,
        requested=str(t.get("requested_patient", "")),
        item=str(t.get("item", "")),
        items=tuple(rec.items.items()),
        person_present=person_present(graph),
        clinician_called=rec.clinician_called,
        kind=kind,
        gait=tuple(sorted(gait(graph).items())),
    )


def _gait_changes(before: TestView, after: TestView) -> list[dict[str, Any]]:
    """A Get Up & Go trial as the gait node tells it."""
    was, now = dict(before.gait), dict(after.gait)
    trial, status = now.get("trial", 0), now.get("status")
    new_trial = trial != was.get("trial") and status == "timing"
    events: list[dict[str, Any]] = []
    if new_trial:
        events.append({"event": "trial", "trial": trial})
    if status == "timing" and now.get("phase") not in ("", "waiting", was.get("phase"), None):
        events.append({"event": "phase", "trial": trial, "phase": now["phase"]})
    if status != was.get("status") or new_trial:
        if status == "timed":
            events.append(
                {
                    "event": "timed",
                    "trial": trial,
                    "tug_seconds": now.get("tug_seconds"),
                    "band": now.get("band"),
                }
            )
        elif status == "void":
            events.append({"event": "trial_void", "trial": trial})
    return events


def _definition(kind: str) -> Definition:
    """The definition the test's items are read by (a timed test has no items; a test this
    package does not ship is read as the Barthel test was before tests had kinds)."""
    return definitions.load(kind if kind in definitions.tests() else "barthel")


def _result(graph: Graph, after: TestView) -> dict[str, Any]:
    if after.kind != TIMED:
        return record(graph, _definition(after.kind)).to_json()
    if dict(after.gait).get("status") != "timed":
        reasons = graph.node("test").attrs.get("void_reasons") or []
        return {
            "test": after.kind,
            "patient": after.patient,
            "timed": False,
            "void_reasons": [str(r) for r in reasons],
        }
    return result(graph, GugRecord(after.patient, after.started))


def test_name(kind: str) -> str:
    """How people call a test: "Barthel test", "Get Up & Go test", or its definition's title."""
    names = {"barthel": "Barthel test", TIMED: "Get Up & Go test"}
    return names.get(kind) or _definition(kind).title


def band_words(result: dict) -> str:
    """A questionnaire result's band as people read it; a provisional one (items the robot could
    not understand wait for the clinician) says so, with the range its total lies in."""
    if result.get("band") is not None:
        return (
            f"{result['band']} dependency"
            if result.get("test", "barthel") == "barthel"
            else result["band"]
        )
    low, high = result.get("total_range") or (result.get("total"), result.get("total"))
    doubtful = [
        i["item"]
        for i in result.get("items", [])
        if i.get("needs_clinician") and not i.get("via") and i.get("points") is None
    ]
    return f"provisional: {low} to {high} until the clinician scores {', '.join(doubtful)}"


def items_in(kind: str) -> int:
    """How many items a test has (0: a timed test)."""
    return 0 if kind == TIMED else len(_definition(kind).order)


def position(item: str, kind: str = "barthel") -> int:
    """An item's place in the test, from 1 (0: not an item)."""
    order = () if kind == TIMED else _definition(kind).order
    return order.index(item) + 1 if item in order else 0


def _item_changes(key: str, before: ItemResult, after: ItemResult) -> list[dict[str, Any]]:
    events: list[dict[str, Any]] = []
    for k, outcome in enumerate(after.outcomes[len(before.outcomes) :], len(before.outcomes) + 1):
        if outcome == "answered":
            continue  # told below with its points, once the status says answered
        event: dict[str, Any] = {"event": outcome, "item": key, "attempt": k}
        if outcome == "interrupted":
            event["event"] = "window_interrupted"
        if outcome in ("not_understood", "unsure"):
            event["heard"] = after.heard
        events.append(event)
    if after.attempts > before.attempts and after.status == "asking":
        events.append({"event": "listening", "item": key, "attempt": after.attempts})
    if after.status != before.status:
        if after.status == "answered":
            event = {"event": "answer", "item": key, "points": after.points, "via": after.via}
            if after.drawing:
                event["drawing"] = True  # for the clinician to score
            events.append(event)
        elif after.status == "unanswered":
            events.append({"event": "unanswered", "item": key})
    return events


def _questionnaire_changes(before: TestView, after: TestView) -> list[dict[str, Any]]:
    """The items reached and what happened in each, in the test's order: an observer that
    joins late, or reads several changes at once, tells every item it passed, each before its
    answer (not only the item the test is at now)."""
    order = _definition(after.kind).order
    was, now = position(before.item, after.kind), position(after.item, after.kind)
    reached = {order[k - 1] for k in range(was + 1, now + 1)}
    if after.item != before.item and now:
        reached.add(after.item)  # the test went back to an item (it does not, but told so)
    events: list[dict[str, Any]] = []
    items = dict(after.items)
    for key in (*order, *(k for k in items if k not in order)):
        if key in reached:
            events.append(
                {
                    "event": "item",
                    "item": key,
                    "position": position(key, after.kind),
                    "of": len(order),
                }
            )
        if key in items:
            events.extend(_item_changes(key, before.of(key), items[key]))
    return events


def changes(before: TestView, after: TestView, graph: Graph) -> list[dict[str, Any]]:
    """The steps of the test between two views of it, in the order a person would tell them."""
    events: list[dict[str, Any]] = []
    if after.requested and after.requested != before.requested:
        events.append({"event": "start_requested", "patient": after.requested})
    began = after.status in ("running", "finished") and after.started != before.started
    new_test = bool(after.started) and began
    if new_test:
        events.append({"event": "started", "patient": after.patient, "test": after.kind})
        before = TestView(person_present=before.person_present)
    ending = after.status == "finished" and (before.running or new_test)
    if not (after.running or ending):
        return events
    if after.kind == "get_up_and_go":
        events.extend(_gait_changes(before, after))
    else:
        events.extend(_questionnaire_changes(before, after))
    if after.running and before.person_present != after.person_present and not new_test:
        events.append({"event": "person_back" if after.person_present else "person_lost"})
    if after.clinician_called and not before.clinician_called:
        unanswered = [k for k, i in after.items if i.status == "unanswered"]
        events.append({"event": "clinician_called", "unanswered": unanswered})
    if ending:
        events.append({"event": "finished", "result": _result(graph, after)})
    return events


def started_since(test: TestView, since: datetime | None) -> bool:
    """The test started at or after ``since`` (an unreadable time is not)."""
    try:
        return since is not None and datetime.fromisoformat(test.started) >= since
    except (TypeError, ValueError):
        return False


class Course:
    """Follows one graph (a replica): ``follow`` after each change gives the new steps, and
    ``current`` is the test as the graph says it now."""

    def __init__(self, since: datetime | None = None) -> None:
        self.since = since
        self.current: TestView | None = None

    def follow(self, graph: Graph) -> list[dict[str, Any]]:
        after = view(graph)
        before, self.current = self.current, after
        if before is None:  # the observer just started
            if started_since(after, self.since):  # its test: told from the start
                return changes(TestView(), after, graph)
            if not after.running:
                return changes(TestView(), TestView(requested=after.requested), graph)
            return [
                {
                    "event": "following",
                    "patient": after.patient,
                    "item": after.item,
                    "position": position(after.item, after.kind),
                    "of": items_in(after.kind),
                    "test": after.kind,
                }
            ]
        return changes(before, after, graph)
