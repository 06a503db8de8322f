"""What CLARC says in a Get Up & Go test (the simulated patient recognises these)."""

from __future__ import annotations

EXPLAIN = (
    "This is the Get Up and Go test. When I say go, stand up from the chair, walk to the line "
    "on the floor at your normal pace, turn round, walk back and sit down again."
)
SIT = "Please, sit down on the chair, with your back against it."
GO = "Ready? Go!"
AGAIN = "Let us do it once more from the start."
DONE = "Thank you, the test is over."
