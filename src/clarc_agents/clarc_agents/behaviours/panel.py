"""The Panel agent's processes, apart from ROS: ``show`` puts the sentence and its options on the
touch screen, ``clear`` blanks it; a tap becomes the percept ``tap``, which the grammar turns into
an answer while one is awaited. Rules: ``grammars/panel.yaml``."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, Protocol

from clarc_agents.behaviours.early_answer import NO_GAP, EarlyAnswer
from dsr_graph.model.graph import Graph
from dsr_graph.rules.runner import ActionContext, Process, RuleRunner


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

    def processes(self) -> dict[str, Process]:
        return {"show": self.show, "clear": self.clear}

    def show(self, ctx: ActionContext) -> str:
        self.screen.display(
            {
                "sid": ctx["sid"],
                "text": ctx["text"],
                "options": ctx["options"],
                "option_points": ctx["points"],
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
            self._early.keep(int(points), item)
            self.log.warning(
                f"tap on {points} points while no answer is awaited: ignored "
                f"unless a window for {item} opens now"
            )
            return False
        return bool(runner.signal("tap", points=int(points)))

    def on_graph(self, runner: RuleRunner, graph: Graph) -> None:
        """A window opened: a tap made just before it, for the same item, is its answer."""
        waiting = graph.edge("person", "answer", "waiting")
        if waiting is None:
            return
        points = self._early.take(str(waiting.attrs.get("item", "")))
        if points is not None:
            runner.signal("tap", points=points)
