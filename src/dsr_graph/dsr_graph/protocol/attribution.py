"""Whose request is it: the DSR server's rule, without ROS. With security on, a signed request
is its signer's, who must own the topic it came on; unsigned or forged, it is refused under
enforce and taken on the ROS graph's word (with an alarm) under permissive. With security off,
the ROS graph's word (protocol/identity.py) is all there is.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from dsr_graph.exceptions import Violation
from dsr_graph.protocol.identity import Sender
from dsr_graph.protocol.security import ENFORCE, OFF, Security
from dsr_graph.protocol.signing import Verified


@dataclass(frozen=True)
class Alarm:
    kind: str  # signature | identity
    message: str
    intruders: tuple[str, ...] = ()
    refused: bool = True  # False: taken all the same (permissive)


@dataclass(frozen=True)
class Attribution:
    agent: str | None  # None: refused
    payload: str  # the request's text (without its signature)
    refusal: Violation | None = None
    alarms: tuple[Alarm, ...] = ()
    proven_signer: str | None = None  # the topic's owner proved itself with this key


def attribute(
    security: Security,
    text: str,
    sender: Sender,
    topic: str,
    owner: str | None,
    strangers: Callable[[], tuple[str, ...]],
) -> Attribution:
    """``sender``: what the ROS graph says; ``owner``: the node the request topic is named after
    (None: the shared topic); ``strangers``: the topic's publishers that are not its owner."""
    if security.mode != OFF:
        signed = security.request(text)
        if isinstance(signed, Verified):
            if owner is None or signed.signer.rsplit("/", 1)[-1] == owner:
                proven = signed.signer if owner is not None else None
                return Attribution(signed.signer, signed.payload, proven_signer=proven)
            problem = f"signed by {signed.signer}, but published on {owner!r}'s topic"
            alarm = Alarm("identity", problem, (signed.signer,))
            refusal = Violation("identity", topic, problem)
            return Attribution(None, signed.payload, refusal, (alarm,))
        problem = f"a request on {topic} is refused: {signed}"
        if security.mode == ENFORCE:
            alarm = Alarm("signature", problem, strangers())
            return Attribution(None, text, Violation("signature", topic, problem), (alarm,))
        taken = (Alarm("signature", problem, (), refused=False),)
        return _by_the_ros_graph(sender, topic, text, taken)
    return _by_the_ros_graph(sender, topic, text, ())


def _by_the_ros_graph(
    sender: Sender, topic: str, text: str, alarms: tuple[Alarm, ...]
) -> Attribution:
    if sender.agent is not None:
        return Attribution(sender.agent, text, alarms=alarms)
    alarm = Alarm("identity", sender.problem, sender.intruders)
    refusal = Violation("identity", topic, sender.problem)
    return Attribution(None, text, refusal, (*alarms, alarm))
