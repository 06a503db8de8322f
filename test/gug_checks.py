"""The issue's tolerances for a Get Up & Go result against the scripted motion it came from,
shared by the unit, executive and system tests."""

import pytest

from clarc_agents.gug.phases import PHASES, STILL


def check_timed(result, motion, still: float = 1.0) -> None:
    """``result`` as stored (``outcome``, ``tug_seconds``, ``reaction_seconds``, ``phases``):
    the total and the reaction within 0.5 s of the script's, each phase within two boundaries'
    0.5 s (the script has no pauses: at most ``still`` s are read between its movements), and
    the parts adding up to the total as stored."""
    assert result["outcome"] == "timed", result
    assert abs(result["tug_seconds"] - motion.total) <= 0.5, (result, motion.total)
    assert abs(result["reaction_seconds"] - motion.reaction) <= 0.5, result
    assert list(result["phases"]) == [*PHASES, STILL]
    assert result["phases"][STILL] <= still, result
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


# ../shared/data/motion/tug_f77_mediapipe33.csv as read by hand (test_real_motion.py says how):
# (start, end) of each movement, seconds from its first frame, and seated again
F77_READ = {
    "rise": (1.07, 2.2),
    "walk_out": (4.1, 13.3),
    "turn": (21.2, 24.4),
    "walk_back": (26.0, 35.6),
    "sit": (35.7, 40.5),
}
F77_TOTAL = 40.5


def boundaries_as_read(moves, read, within: float = 0.5) -> None:
    """Each movement's (start, end) within ``within`` s of the reading's, in PHASES order."""
    for phase, (start, end) in zip(PHASES, moves, strict=True):
        read_start, read_end = read[phase]
        assert abs(start - read_start) <= within, (phase, moves)
        assert abs(end - read_end) <= within, (phase, moves)
