"""One thing the robot says (Speech) and shows (Panel), as PELEA writes it in the DSR: every test
speaks through it (pure)."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Sentence:
    text: str
    needs_person: bool = True  # speech stops and the screen clears if the person leaves
    item: str = ""
    options: list[str] = field(default_factory=list)  # shown as buttons
    option_points: list[float] = field(default_factory=list)
    shows: list[str] = field(default_factory=list)  # pictures, targets or a written instruction
    input: str = ""  # what the screen takes: options, targets, drawing, or nothing
