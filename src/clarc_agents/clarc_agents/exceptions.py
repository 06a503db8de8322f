"""Every error of CLARC's agents, in one place (the stand-ins' are in ``clarc_sim.exceptions``).
Each derives from ``dsr_graph.exceptions.DsrError``, the base of every error of the suite, so a
node's main turns any of them into one fatal line and exit code 1."""

from __future__ import annotations

from dsr_graph.exceptions import DsrError


class NoPlan(DsrError):
    """The planner proved the goal unreachable from this state."""


class ScenarioError(DsrError, ValueError):
    """A scenario file is not usable; the message names the file, the line and what is wrong."""


class AudioError(DsrError, ValueError):
    """A recording the recogniser cannot take (not 16-bit PCM WAV or raw); the message names the
    file and what is wrong."""


class ModelError(DsrError):
    """A recogniser's model files are missing or not the ones pinned (their SHA-256 differs);
    the message names the package and the file."""


class DefinitionError(DsrError, ValueError):
    """A test definition file is not usable; the message names the file, the line and what is
    wrong."""


class NotATrial(DsrError, ValueError):
    """Skeleton samples that do not hold a whole Get Up & Go trial (no rise, no walk, no turn,
    not seated again); the message says which."""


class InvalidTrial(NotATrial):
    """A Get Up & Go trial that ended but does not count (not seated at go, the line not
    reached, no turn): it is void, and the message is the reason the clinician reads."""


class TrialGap(InvalidTrial):
    """Frames are missing from a Get Up & Go trial for longer than a movement may hide in (the
    Kinect or Person was down, the analyser joined late): it can never be timed."""
