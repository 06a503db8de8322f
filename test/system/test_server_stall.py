"""A DSR server stalled for longer than the DDS lease (SIGSTOP, then SIGCONT): every agent works
with it again. Fast DDS drops the frozen server's participant; some agents' participants never
match it again, or the server never learns their node names again. Such an agent finds it out (a
probe, protocol/cut_off.py; a second refusal for an unknown node, ros/agent.py) and ends with
exit code 5 (dsr_node.CUT_OFF), and its launch restarts it, as the test does here."""

import json
import os
import signal
import time

import pytest

from dsr_graph.protocol.cut_off import CUT_OFF_AFTER, PROBE_EVERY
from dsr_graph.protocol.identity import NODE_INFO_WAIT

from ros_processes import agent_in_session, new_session, send_and_wait, start_synced, wait_for

STALL = 4.0  # seconds: twice the suite's participant lease (fastdds_profile.xml)
ANSWER_WITHIN = 3.0  # seconds the rule agent takes to echo a sentence, when it hears it
RULE = {
    "name": "echo",
    "when": [{"edge": ["test", "test_part", "is_in"], "attrs": {"sentence_id": "$sid"}}],
    "once_per": ["$sid"],
    "during": [{"set_node_attrs": ["test_part", {"level": "$sid"}]}],
    "process": "instant",
    "after": [{"set_node_attrs": ["test_part", {"sentence_id": "$sid"}]}],
}


def start_echo(ros, grammar):
    argv = ["dsr_rule_agent", "--ros-args", "-r", "__node:=echo"]
    return ros.procs.start("echo", [*argv, "-p", f"grammar_file:={grammar}"])


def sentence(sid: int) -> dict:
    attrs = {"sentence_id": sid}
    return {
        "ops": [
            {
                "op": "set_edge_attrs",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attrs": attrs,
            }
        ]
    }


@pytest.mark.timeout(240)
def test_an_agent_works_with_a_server_that_stalled_beyond_the_lease(ros):
    from dsr_graph.ros.agent import DsrAgent
    from dsr_graph.ros.dsr_node import CUT_OFF

    start_synced(ros)
    grammar = ros.tmp / "echo.yaml"
    grammar.write_text(json.dumps([RULE]))
    before = agent_in_session(ros)
    setup = {
        "ops": [
            {"op": "insert_node", "name": "test", "type": "test"},
            {"op": "insert_node", "name": "test_part", "type": "test_part"},
            {"op": "insert_edge", "from": "test", "to": "test_part", "type": "is_in"},
        ]
    }
    assert send_and_wait(ros, before, setup).accepted
    echo = start_echo(ros, grammar)
    wait_for(lambda: "running 1 rules" in ros.procs.log("echo"), 30, "the rule agent")
    assert send_and_wait(ros, before, sentence(1)).accepted
    wait_for(
        lambda: before.graph.node("test_part").attrs.get("sentence_id") == 1,
        20,
        "the echo before the stall",
        ros.session,
    )
    server = ros.procs.procs["server"]
    os.kill(server.pid, signal.SIGSTOP)
    try:
        time.sleep(STALL)
    finally:
        os.kill(server.pid, signal.SIGCONT)
    # a participant made after the stall (the test's own may be cut off now, as any agent's)
    client = new_session(ros.domain_id, "after_stall")
    try:
        after = DsrAgent(describe=False)
        after.setup(client.node, timeout_sec=30)
        wait_for(lambda: after.ready, 30, "an agent made after the stall", client)
        restarts, sid = 0, 1
        # unmatched: found within CUT_OFF_AFTER and a probe; its name lost: refused twice, each
        # after the server's NODE_INFO_WAIT
        deadline = time.monotonic() + max(CUT_OFF_AFTER + PROBE_EVERY, 2 * NODE_INFO_WAIT) + 30
        while True:
            assert time.monotonic() < deadline, ros.procs.tails()
            code = echo.poll()
            if code is not None:  # the launch's part: an agent that ended is started again
                log = ros.procs.log("echo")
                assert code == CUT_OFF and "cut off from the DSR server" in log, log
                restarts += 1
                assert restarts == 1, log
                ros.procs.procs.pop("echo")
                echo = start_echo(ros, grammar)
            sid += 1
            after.send(sentence(sid))
            spin_until(client, lambda s=sid: echoed(after, s), ANSWER_WITHIN)
            if echoed(after, sid):
                break
    finally:
        client.close()
    assert echo.poll() is None


def echoed(agent, sid: int) -> bool:
    return agent.graph.node("test_part").attrs.get("sentence_id") == sid


def spin_until(session, done, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while not done() and time.monotonic() < deadline:
        session.executor.spin_once(timeout_sec=0.1)
