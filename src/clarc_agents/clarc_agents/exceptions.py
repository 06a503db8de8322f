"""Every error of the CLARC packages (agents and stand-ins), in one place. Each derives from
``dsr_graph.exceptions.DsrError``, the base of every error of the suite, so a node's main turns
any of them into one fatal line and exit code 1."""

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


class InvalidResult(DsrError, ValueError):
    """A result that does not describe a test (Barthel or Get Up & Go); the message says what is
    wrong."""


class UnknownTest(InvalidResult):
    """No stored test has that id."""


class UnknownPatient(InvalidResult):
    """No patient record has that id."""


class AlreadyValidated(InvalidResult):
    """A clinician validated this result already; the message says who and when."""


class ResultChanged(InvalidResult):
    """A result changed (a score) since the version a clinician validates."""


class AccountError(InvalidResult):
    """A user account cannot be made or changed as asked; the message says why."""


class SkeletonRecordingError(ScenarioError):
    """A skeleton recording that cannot be read, imported or placed; the message names the
    file, the line and what is wrong."""


class NotATrial(DsrError, ValueError):
    """Skeleton samples that do not hold a whole Get Up & Go trial (no rise, no walk, no turn,
    not seated again); the message says which."""


class InvalidTrial(NotATrial):
    """A Get Up & Go trial that ended but does not count (not seated at go, the line not
    reached, no turn): it is void, and the message is the reason the clinician reads."""


class TrialGap(InvalidTrial):
    """Frames are missing from a Get Up & Go trial for longer than a movement may hide in (the
    Kinect or Person was down, the analyser joined late): it can never be timed."""
