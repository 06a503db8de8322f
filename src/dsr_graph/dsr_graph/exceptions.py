"""Every error of dsr_graph, in one place. Each derives from ``DsrError`` (so does every error of
the CLARC packages, in ``clarc_agents.exceptions`` and ``clarc_sim.exceptions``): a node's main
turns any of them into one fatal line and exit code 1. A rejection names the element and the
rule it broke."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Violation:
    """One broken rule: which rule, which element, what is wrong, and where in a request.

    ``rule`` is a short stable identifier (e.g. ``rt-single-parent``) that scripts can match;
    ``element`` names the node (``node 'robot'``) or edge (``edge 'room'->'robot' (RT)``);
    ``at`` locates it in a transaction (``op 2 (insert_edge)``, ``precondition 0``) or a file.
    """

    rule: str
    element: str
    message: str
    at: str | None = None

    def __str__(self) -> str:
        where = f"{self.at}: " if self.at else ""
        return f"{where}{self.element}: {self.rule}: {self.message}"

    def located(self, at: str) -> Violation:
        return Violation(self.rule, self.element, self.message, at)

    def to_json(self) -> dict:
        return {"rule": self.rule, "element": self.element, "message": self.message, "at": self.at}


class DsrError(Exception):
    """Base of every error raised by dsr_graph."""


class RuleViolation(DsrError):
    """A change or a file broke a rule of the graph; ``violation`` says which and where."""

    def __init__(self, violation: Violation):
        super().__init__(str(violation))
        self.violation = violation


class TransactionRejected(RuleViolation):
    """A transaction was refused as a whole; the graph is exactly as it was before it."""


class FormatError(DsrError):
    """A JSON document (world, snapshot, transaction, vocabulary) does not follow the schema."""


class VocabularyError(DsrError):
    """A vocabulary file is malformed or contradicts another one."""


class WorldLoadError(DsrError):
    """A world file could not be read at all (not JSON, unknown format)."""


class LookupFailed(DsrError):
    """A query named a node that does not exist or is not part of the geometric tree."""


class OutsideHistory(LookupFailed):
    """A transform was asked for a time the RT history does not hold (model/rt_history.py)."""


class TimedOutError(DsrError):
    """Something this process waits for (the server, a snapshot, an answer) did not come in time."""


class GrammarError(DsrError):
    """A rule is malformed; the message names the rule and the part."""


class NotRigidError(DsrError, ValueError):
    """The matrix or pose description is not a rigid transform; the message says why."""


class ValueTypeError(DsrError, ValueError):
    """A value does not fit its declared attribute type."""


class MissingBlob(DsrError, ValueError):
    """A binary value's reference whose bytes have not come (protocol/blobs.py)."""

    def __init__(self, digest: str):
        super().__init__(f"the binary value {digest} did not come on the blob topic")
        self.digest = digest


class SeqUnavailable(DsrError, LookupError):
    """The graph at that seq is not in the history (before the viewer started, or in a gap)."""


class StateDirLocked(DsrError):
    """Another server holds this state directory."""


class StateMismatch(DsrError):
    """The state directory holds a graph made from another world than the one asked for."""


class CorruptState(DsrError):
    """The stored state cannot be read back consistently; the message says where."""


class RecordingError(DsrError):
    """A file that is not a DSR recording (dsr record), or one that cannot be read."""


class JsonRefused(DsrError, ValueError):
    """A JSON text from outside was refused (too many bytes, too deep, NaN, a huge number)."""


class SignatureRefused(DsrError, ValueError):
    """A DSR message not signed, signed by someone unknown or not allowed, or changed since."""


class KeystoreError(DsrError):
    """A keystore that cannot be used (missing, malformed, a node without its key)."""
