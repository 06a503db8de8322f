"""Signed DSR traffic through real processes (DSR_KEYSTORE, DSR_SECURITY=enforce): the delta
stream is the server's alone (a forged delta is dropped by every replica, with an alarm, and the
server's real delta with that seq still applies), and a stopped agent's name cannot be taken by
a process without its key."""

import json
import time
from pathlib import Path

from std_msgs.msg import String

from dsr_graph.formats.keystore import Keystore
from dsr_graph.protocol.signing import Signer

from ros_processes import agent_in_session, send_and_wait, snapshot_via, wait_for

WORLD_CLARC = Path(__file__).resolve().parents[2] / "worlds" / "clarc_room.json"


def keystore(path, *names):
    ks, _ = Keystore.init(path)
    for name in names:
        ks.add(name)
    return ks


def canonical(doc):
    return json.dumps(doc, sort_keys=True)


def without_agents(snapshot):
    """A snapshot less the agents' info nodes (and their edges) and its seq: what the server
    writes of agents that come and go, beside what a test's requests could change."""
    agents = {n["name"] for n in snapshot["nodes"] if n["type"] == "agent"}
    nodes = [n for n in snapshot["nodes"] if n["name"] not in agents]
    edges = [e for e in snapshot.get("edges", []) if not {e.get("from"), e.get("to")} & agents]
    return {**snapshot, "nodes": nodes, "edges": edges, "seq": None}


def text_of(graph):
    return graph.node("panel").attrs.get("text")


class Alarms:
    def __init__(self, ros):
        from dsr_graph.ros.qos import qos_stream

        self.seen = []
        ros.session.node.create_subscription(
            String, "dsr/alarms", lambda m: self.seen.append(m.data), qos_stream()
        )

    def of(self, kind):
        return [json.loads(a[: a.rfind(',"sig":')] + "}") for a in self.seen if kind in a]


def test_forged_deltas_are_dropped_by_replicas_with_an_alarm_and_the_real_one_applies(
    ros, monkeypatch
):
    ks = keystore(ros.tmp / "ks", "/test_client", "/intruder", "/dsr_viewer")
    monkeypatch.setenv("DSR_KEYSTORE", str(ks.root))  # this test's replica and every process
    ros.procs.start_server(ros.tmp / "state", world=WORLD_CLARC)
    agent = agent_in_session(ros, timeout=30)
    alarms = Alarms(ros)
    before = canonical(snapshot_via(ros.session))
    seq = agent.replica.seq
    forged = json.dumps(
        {
            "seq": seq + 1,
            "stamp": time.time(),
            "agent": "/cgamed",
            "id": "forged-1",
            "ops": [{"op": "set_node_attrs", "node": "panel", "attrs": {"text": "Mallory"}}],
        }
    )
    pub = ros.session.node.create_publisher(String, "dsr/deltas", 10)
    wait_for(lambda: pub.get_subscription_count() > 0, 10, "a replica", ros.session)
    for text in (
        forged,  # not signed
        Signer("/dsr_server", ks.private_key("/intruder")).sign("dsr/deltas", forged),
        Signer("/intruder", ks.private_key("/intruder")).sign("dsr/deltas", forged),
        Signer("/dsr_server", ks.private_key("/dsr_server")).sign("dsr/heartbeat", forged),
    ):
        pub.publish(String(data=text))
    wait_for(lambda: agent.forged >= 4, 10, "the replica to drop four forged deltas", ros.session)
    wait_for(lambda: alarms.of("signature"), 10, "an alarm", ros.session)
    alarm = alarms.of("signature")[0]
    assert alarm["node"] == "/test_client" and alarm["topic"] == "dsr/deltas"
    assert agent.replica.seq == seq and text_of(agent.graph) != "Mallory"
    assert canonical(snapshot_via(ros.session)) == before
    # the server's own delta with that seq is applied, not taken for a duplicate
    done = send_and_wait(
        ros,
        agent,
        {"ops": [{"op": "set_node_attrs", "node": "panel", "attrs": {"text": "real"}}]},
    )
    assert done.accepted and done.seq == seq + 1
    wait_for(lambda: agent.replica.seq == seq + 1, 10, "the real delta", ros.session)
    assert text_of(agent.graph) == "real"


def test_a_stopped_agent_s_name_cannot_be_taken_without_its_key(ros, monkeypatch):
    ks = keystore(ros.tmp / "ks", "/speech")
    other = keystore(ros.tmp / "other", "/speech")  # a key for the name, not the suite's
    monkeypatch.setenv("DSR_KEYSTORE", str(ks.root))
    ros.procs.start_server(ros.tmp / "state", world=WORLD_CLARC)
    snapshot_via(ros.session, timeout=20)
    alarms = Alarms(ros)
    ros.procs.start("speech", ["speech"])
    wait_for(lambda: "agent up" in ros.procs.log("speech"), 30, "the speech agent")
    assert ros.procs.stop("speech") == 0
    before = canonical(without_agents(snapshot_via(ros.session)))
    request = json.dumps(
        {"ops": [{"op": "set_node_attrs", "node": "panel", "attrs": {"text": "impostor"}}]}
    )
    # a process without the suite's keystore: its requests are not signed
    done = ros.procs.run(
        "dsr", "apply", "-", "--ros-args", "-r", "__node:=speech", input=request, DSR_SECURITY="off"
    )
    assert done.returncode == 1 and "signature" in done.stdout, done.stdout + done.stderr
    # a request signed with another keystore's key for /speech: refused, with its id
    rejections = []
    ros.session.node.create_subscription(
        String, "dsr/rejections", lambda m: rejections.append(m.data), 10
    )
    pub = ros.session.node.create_publisher(String, "dsr/transactions/speech", 10)
    wait_for(lambda: pub.get_subscription_count() > 0, 20, "the server", ros.session)
    forged = json.dumps({**json.loads(request), "id": "forged-2", "agent": "/speech"})
    pub.publish(
        String(
            data=Signer("/speech", other.private_key("/speech")).sign("dsr/transactions", forged)
        )
    )
    wait_for(lambda: any("forged-2" in r for r in rejections), 10, "a rejection", ros.session)
    [refused] = [r for r in rejections if "forged-2" in r]
    assert '"rule":"signature"' in refused and "does not match" in refused
    wait_for(lambda: alarms.of("signature"), 10, "the server's alarm", ros.session)
    assert alarms.of("signature")[0]["topic"].endswith("dsr/transactions/speech"), alarms.of(
        "signature"
    )
    assert "refusing requests on /dsr/transactions/speech" in ros.procs.log("server")
    # (the server may mark the stopped /speech gone meanwhile: its info node is the server's)
    assert canonical(without_agents(snapshot_via(ros.session))) == before
    # the real /speech comes back with its key: its requests are its own again
    done = ros.procs.run(
        "dsr", "apply", "-", "--ros-args", "-r", "__node:=speech", input=request, timeout=60
    )
    assert done.returncode == 0 and "accepted" in done.stdout, done.stdout + done.stderr
