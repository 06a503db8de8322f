"""The Panel agent's processes, apart from ROS: ``show`` puts the sentence and its options on the
touch screen, ``clear`` blanks it; a tap becomes the percept ``tap``, which the grammar turns into
an answer while one is awaited. Rules: ``grammars/panel.yaml``.

Beyond options, the screen shows what an item needs (``shows``: pictures, shapes, a written
instruction) and takes what it asks for (``input``): touches on shapes, scored when there are as
many as the item's parts (percept ``touched``: a point per stage touched in order), those so far
kept on the window until then (percept ``touching``: PELEA scores them if the window ends
first), or a drawing, kept for the clinician (percept ``drawn``: SVG path data)."""

from __future__ import annotations

import re
import time
from collections.abc import Callable
from typing import Any, Protocol

from clarc_agents.behaviours.early_answer import NO_GAP, EarlyAnswer
from clarc_agents.questionnaire.answers import touched_in_order
from clarc_agents.questionnaire.item_options import awaited_item, item_on_screen
from dsr_graph.model.graph import Graph
from dsr_graph.rules.runner import ActionContext, Process, RuleRunner

# SVG path data of straight strokes, as the screen records a finger: M x y L x y ...
DRAWING = re.compile(r"^[MLZ0-9 ,.\-]+$")
MAX_DRAWING = 200_000  # characters: a page of handwriting is a few thousand


class Screen(Protocol):
    def display(self, content: dict[str, Any]) -> None: ...


class PanelBehaviour:
    def __init__(
        self,
        screen: Screen,
        log,
        now: Callable[[], float] = time.monotonic,
        server_gap: Callable[[], tuple[float, float]] = lambda: NO_GAP,
    ):
        self.screen = screen
        self.log = log
        self._early = EarlyAnswer(now, server_gap)  # a tap made just before its window opened
        self._touched: tuple[Any, list[str]] = (None, [])  # (the window, shapes touched in it)

    def processes(self) -> dict[str, Process]:
        return {"show": self.show, "clear": self.clear}

    def show(self, ctx: ActionContext) -> str:
        self._early.asked()
        self.screen.display(
            {
                "sid": ctx["sid"],
                "text": ctx["text"],
                "options": ctx["options"],
                "option_points": ctx["points"],
                "shows": ctx["shows"],
                "input": ctx["input"],
            }
        )
        return "done"

    def clear(self, ctx: ActionContext) -> str:
        self.screen.display({"clear": True})
        return "done"

    def on_tap(self, runner: RuleRunner, graph: Graph, points: Any) -> bool:
        """A tap on the option worth ``points``. Refused, with a warning that says why, when
        ``points`` is not an option of the item the DSR shows, or when no answer is awaited (a
        valid tap is then kept a moment for the window about to open, see ``on_graph``)."""
        shown = graph.edge("test", "test_part", "is_in")
        options = [] if shown is None else list(shown.attrs.get("option_points", []))
        item = "" if shown is None else str(shown.attrs.get("item", ""))
        is_number = isinstance(points, (int, float)) and not isinstance(points, bool)
        if not is_number or points not in options:
            worth = [int(p) for p in options]
            self.log.warning(
                f"tap on {points!r} points refused: not an option of "
                f"{item or 'the screen'} (its options are worth {worth})"
            )
            return False
        if graph.edge("person", "answer", "waiting") is None:
            self._early.keep(("tap", int(points)), item)
            self.log.warning(
                f"tap on {points} points while no answer is awaited: ignored "
                f"unless a window for {item} opens now"
            )
            return False
        return bool(runner.signal("tap", points=int(points)))

    def on_input(self, runner: RuleRunner, graph: Graph, entry: dict[str, Any]) -> bool:
        """What the screen took: a tap on an option (``points``), a touch on a shape
        (``target``) or a finished drawing (``drawing``)."""
        if "target" in entry:
            return self.on_target(runner, graph, entry["target"])
        if "drawing" in entry:
            return self.on_drawing(runner, graph, entry["drawing"])
        return self.on_tap(runner, graph, entry.get("points"))

    def _awaited(self, graph: Graph, kind: str, what: str, early: tuple | None = None):
        """The window and the item it awaits, if it is a ``kind`` item; else a warning. With no
        window open, ``early`` (what the screen took) is kept a moment for the window of the
        item on the screen (the patient did not wait for the robot to finish asking)."""
        waiting, item = graph.edge("person", "answer", "waiting"), awaited_item(graph)
        if item is None or item.kind != kind:
            on_screen = item_on_screen(graph)
            if early is not None and waiting is None and on_screen:
                kept = self._early.peek(on_screen)
                if early[0] == "targets" and kept is not None and kept[0] == "targets":
                    early = ("targets", [*kept[1], *early[1]])  # touched one after another
                self._early.keep(early, on_screen)
                self.log.warning(
                    f"{what} while no answer is awaited: kept unless a window for {on_screen} "
                    "opens now"
                )
                return None, None
            self.log.warning(f"{what} refused: no answer of that kind is awaited")
            return None, None
        return waiting, item

    def on_target(self, runner: RuleRunner, graph: Graph, target: Any) -> bool:
        shown = graph.edge("test", "test_part", "is_in")
        shapes = [] if shown is None else [str(s).lower() for s in shown.attrs.get("shows", [])]
        if not isinstance(target, str) or target.lower() not in shapes:
            self.log.warning(f"touch on {target!r} refused: the screen shows {shapes}")
            return False
        early = ("targets", [target])
        waiting, item = self._awaited(graph, "touches", f"touch on {target!r}", early)
        if item is None:
            return False
        window, touched = self._touched
        if window is not waiting:  # a new window (or a restarted Panel): what it holds so far
            so_far = str(waiting.attrs.get("touched", ""))
            window, touched = waiting, [t for t in so_far.split(", ") if t]
            self._touched = (window, touched)
        touched.append(target.lower())
        points, heard = touched_in_order(item, touched), ", ".join(touched)
        if len(touched) < len(item.parts):  # kept on the window: scored if it ends so
            return bool(runner.signal("touching", points=points, heard=heard))
        self._touched = (None, [])
        return bool(runner.signal("touched", points=points, heard=heard))

    def on_drawing(self, runner: RuleRunner, graph: Graph, drawing: Any) -> bool:
        if (
            not isinstance(drawing, str)
            or not drawing.strip()
            or len(drawing) > MAX_DRAWING
            or not DRAWING.match(drawing)
        ):
            self.log.warning(
                f"drawing refused: SVG path data of at most {MAX_DRAWING} characters "
                f"(M x y L x y ...) is expected, got {str(drawing)[:40]!r}"
            )
            return False
        _, item = self._awaited(graph, "drawing", "drawing", ("drawing", drawing.strip()))
        if item is None:
            return False
        return bool(runner.signal("drawn", drawing=drawing.strip()))

    def on_graph(self, runner: RuleRunner, graph: Graph) -> None:
        """A window opened: a tap, a drawing or touches made just before it, for the same item,
        are its answer."""
        waiting = graph.edge("person", "answer", "waiting")
        if waiting is None:
            return
        early = self._early.take(str(waiting.attrs.get("item", "")))
        if early is None:
            return
        kind, value = early
        if kind == "tap":
            runner.signal("tap", points=value)
        elif kind == "drawing":
            runner.signal("drawn", drawing=value)
        else:
            for target in value:
                self.on_target(runner, graph, target)
