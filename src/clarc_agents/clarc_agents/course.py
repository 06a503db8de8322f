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
not_understood (item, heard, attempt), skip (item), window_interrupted (item, attempt),
unanswered (item), person_lost, person_back, clinician_called (unanswered), finished (result).
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from clarc_agents.barthel.items import ORDER
from clarc_agents.pelea.high_to_low import item_node
from clarc_agents.pelea.low_to_high import person_present, record
from dsr_graph.model.graph import Graph


@dataclass(frozen=True)
class ItemView:
    status: str = ""
    attempts: int = 0
    outcomes: tuple[str, ...] = ()
    points: int | None = None
    via: str | None = None
    heard: str = ""


@dataclass(frozen=True)
class TestView:
    status: str = ""
    patient: str = ""
    started: str = ""
    requested: str = ""  # the patient a pending Start is for
    item: str = ""
    items: tuple[tuple[str, ItemView], ...] = ()
    person_present: bool = False
    clinician_called: bool = False

    @property
    def running(self) -> bool:
        return self.status == "running"

    def of(self, item: str) -> ItemView:
        return dict(self.items).get(item, ItemView())


def view(graph: Graph) -> TestView:
    test = graph.find("test")
    if test is None:
        return TestView()
    items = []
    for key in ORDER:
        node = graph.find(item_node(key))
        if node is None:
            continue
        a = node.attrs
        points = int(a["answer"]) if a.get("status") == "answered" and "answer" in a else None
        items.append(
            (
                key,
                ItemView(
                    str(a.get("status", "")),
                    int(a.get("attempts", 0)),
                    tuple(a.get("outcomes", ())),
                    points,
                    a.get("via"),
                    str(a.get("heard", "")),
                ),
            )
        )
    t = test.attrs
    return TestView(
        status=str(t.get("status", "")),
        patient=str(t.get("patient", "")),
        started=str(t.get("started", "")),
        requested=str(t.get("requested_patient", "")),
        item=str(t.get("item", "")),
        items=tuple(items),
        person_present=person_present(graph),
        clinician_called=bool(t.get("clinician_called", False)),
    )


def _position(item: str) -> int:
    return ORDER.index(item) + 1 if item in ORDER else 0


def _item_changes(key: str, before: ItemView, after: ItemView) -> list[dict[str, Any]]:
    events: list[dict[str, Any]] = []
    for k, outcome in enumerate(after.outcomes[len(before.outcomes) :], len(before.outcomes) + 1):
        if outcome == "answered":
            continue  # told below with its points, once the status says answered
        event: dict[str, Any] = {"event": outcome, "item": key, "attempt": k}
        if outcome == "interrupted":
            event["event"] = "window_interrupted"
        if outcome == "not_understood":
            event["heard"] = after.heard
        events.append(event)
    if after.attempts > before.attempts and after.status == "asking":
        events.append({"event": "listening", "item": key, "attempt": after.attempts})
    if after.status != before.status:
        if after.status == "answered":
            events.append(
                {"event": "answer", "item": key, "points": after.points, "via": after.via}
            )
        elif after.status == "unanswered":
            events.append({"event": "unanswered", "item": key})
    return events


def changes(before: TestView, after: TestView, graph: Graph) -> list[dict[str, Any]]:
    """The steps of the test between two views of it, in the order a person would tell them."""
    events: list[dict[str, Any]] = []
    if after.requested and after.requested != before.requested:
        events.append({"event": "start_requested", "patient": after.requested})
    began = after.status in ("running", "finished") and after.started != before.started
    new_test = bool(after.started) and began
    if new_test:
        events.append({"event": "started", "patient": after.patient})
        before = TestView(person_present=before.person_present)
    ending = after.status == "finished" and (before.running or new_test)
    if not (after.running or ending):
        return events
    if after.item != before.item:
        events.append({"event": "item", "item": after.item, "position": _position(after.item)})
    for key, item in after.items:
        events.extend(_item_changes(key, before.of(key), item))
    if after.running and before.person_present != after.person_present and not new_test:
        events.append({"event": "person_back" if after.person_present else "person_lost"})
    if after.clinician_called and not before.clinician_called:
        unanswered = [k for k, i in after.items if i.status == "unanswered"]
        events.append({"event": "clinician_called", "unanswered": unanswered})
    if ending:
        events.append({"event": "finished", "result": record(graph).to_json()})
    return events


def started_since(test: TestView, since: datetime | None) -> bool:
    """The test started at or after ``since`` (an unreadable time is not)."""
    try:
        return since is not None and datetime.fromisoformat(test.started) >= since
    except (TypeError, ValueError):
        return False


class Course:
    """Follows one graph (a replica): ``follow`` after each change gives the new steps."""

    def __init__(self, since: datetime | None = None) -> None:
        self.since = since
        self._view: TestView | None = None

    def follow(self, graph: Graph) -> list[dict[str, Any]]:
        after = view(graph)
        before, self._view = self._view, after
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
                    "position": _position(after.item),
                }
            ]
        return changes(before, after, graph)
