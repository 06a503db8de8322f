"""The Panel agent's processes, apart from ROS: ``show`` puts the sentence and its options on the
touch screen, ``clear`` blanks it; a tap becomes the percept ``tap``, which the grammar turns into
an answer while one is awaited. Rules: ``grammars/panel.yaml``."""

from __future__ import annotations

from typing import Any, Protocol

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

    def on_tap(self, runner: RuleRunner, points: int) -> bool:
        """A tap on the option worth ``points``; False when no answer is awaited."""
        if runner.signal("tap", points=points):
            return True
        self.log.info(f"tap on {points} points while no answer is awaited: ignored")
        return False
