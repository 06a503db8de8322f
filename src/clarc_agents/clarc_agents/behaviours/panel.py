"""The Panel agent's processes, apart from ROS: ``show`` puts the sentence and its options on the
touch screen, ``clear`` blanks it; a tap becomes the percept ``tap``, which the grammar turns into
an answer while one is awaited. Rules: ``grammars/panel.yaml``."""

from __future__ import annotations

from typing import Any, Protocol

from dsr_graph.model.graph import Graph
from dsr_graph.rules.runner import ActionContext, Process, RuleRunner


class Screen(Protocol):
    def display(self, content: dict[str, Any]) -> None: ...


class PanelBehaviour:
    def __init__(self, screen: Screen, log):
        self.screen = screen
        self.log = log

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
        """A tap on the option worth ``points``. Refused, with a warning that says why, when no
        answer is awaited or when ``points`` is not an option of the item the DSR shows."""
        waiting = graph.edge("person", "answer", "waiting")
        if waiting is None:
            self.log.warning(f"tap on {points!r} points while no answer is awaited: ignored")
            return False
        shown = graph.edge("test", "test_part", "is_in")
        options = [] if shown is None else list(shown.attrs.get("option_points", []))
        if (
            isinstance(points, bool)
            or not isinstance(points, (int, float))
            or points not in options
        ):
            item = waiting.attrs.get("item", "?")
            self.log.warning(
                f"tap on {points!r} points refused: not an option of {item} "
                f"(its options are worth {[int(p) for p in options]})"
            )
            return False
        if runner.signal("tap", points=int(points)):
            return True
        self.log.warning(f"tap on {points} points while no answer is awaited: ignored")
        return False
