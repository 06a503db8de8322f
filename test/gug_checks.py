"""The issue's tolerances for a Get Up & Go result against the scripted motion it came from,
shared by the unit, executive and system tests."""

import pytest

from clarc_agents.gug.phases import PHASES, STILL


def check_timed(result, motion) -> None:
    """``result`` as stored (``outcome``, ``tug_seconds``, ``reaction_seconds``, ``phases``):
    the total and the reaction within 0.5 s of the script's, each phase within two boundaries'
    0.5 s (the script has no pauses: at most a short one is read between two movements), and
    the parts adding up to the total as stored."""
    assert result["outcome"] == "timed", result
    assert abs(result["tug_seconds"] - motion.total) <= 0.5, (result, motion.total)
    assert abs(result["reaction_seconds"] - motion.reaction) <= 0.5, result
    assert list(result["phases"]) == [*PHASES, STILL]
    assert result["phases"][STILL] <= 1.0, result
    for phase in PHASES:
        assert abs(result["phases"][phase] - getattr(motion, phase)) <= 1.0, (phase, result)
    parts = result["reaction_seconds"] + sum(result["phases"].values())
    assert parts == pytest.approx(result["tug_seconds"], abs=0.011)


def as_result(gait: dict) -> dict:
    """The gait node's attributes as the stored result has them."""
    phases = dict(zip(PHASES, gait["phase_seconds"], strict=True))
    return {
        "outcome": gait["status"],
        "tug_seconds": gait["tug_seconds"],
        "reaction_seconds": gait["reaction_seconds"],
        "phases": {**phases, STILL: gait["still_seconds"]},
    }
