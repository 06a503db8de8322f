"""The errors of CLARC's stand-ins (the hospital's results store, its users, the patient's
recordings). Each derives from ``dsr_graph.exceptions.DsrError`` (through the agents' errors
where it is one of them), so a node's main turns any of them into one fatal line and exit
code 1."""

from __future__ import annotations

from clarc_agents.exceptions import ScenarioError
from dsr_graph.exceptions import DsrError


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
