"""Who writes what, through the real topics: a node cannot write as another running node, a
write outside the policy is refused with the graph unchanged, and hostile requests on a real
request topic leave the server up and the graph as it was. Each test runs twice: with DSR
security off (identity from the ROS graph) and enforced (DSR_KEYSTORE: identity from
signatures; this test's own requests signed with its node's key)."""

import json
import math
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from std_msgs.msg import String

from dsr_graph.formats.keystore import Keystore
from dsr_graph.protocol.security import Security

from ros_processes import snapshot_via, wait_for

WORLD_CLARC = Path(__file__).resolve().parents[2] / "worlds" / "clarc_room.json"

WORLD_POLICY = """
version: 1
agents:
  - name: /writer          # may touch the panel's text, nothing else
    priority: 1
    attributes: [text]
"""


@pytest.fixture(params=["off", "enforce"], autouse=True)
def security(request, tmp_path, monkeypatch):
    if request.param == "enforce":
        keystore, _ = Keystore.init(tmp_path / "keystore")
        for name in ("/test_client", "/speech", "/writer"):
            keystore.add(name)
        monkeypatch.setenv("DSR_KEYSTORE", str(keystore.root))
    else:
        monkeypatch.delenv("DSR_KEYSTORE", raising=False)
    monkeypatch.setenv("DSR_SECURITY", request.param)
    return request.param


def canonical(doc):
    return json.dumps(doc, sort_keys=True)


class Requests:
    """Publishes on a request topic from a node of the test's session, and collects the server's
    verdicts (deltas and rejections) by request id."""

    def __init__(self, ros, topic):
        from dsr_graph.ros.qos import qos_stream

        self.ros = ros
        node = ros.session.node
        self.security = Security.from_environment(node.get_fully_qualified_name())
        self.verdicts = {}
        self.alarms = []
        node.create_subscription(String, "dsr/deltas", self._verdict, qos_stream())
        node.create_subscription(String, "dsr/rejections", self._verdict, qos_stream())
        node.create_subscription(
            String, "dsr/alarms", lambda m: self.alarms.append(json.loads(m.data)), qos_stream()
        )
        self.pub = node.create_publisher(String, topic, qos_stream())
        wait_for(
            lambda: (
                self.pub.get_subscription_count() > 0
                and node.count_publishers("dsr/rejections") > 0
                and node.count_publishers("dsr/deltas") > 0
            ),
            20,
            f"the server to take requests on {topic}",
            ros.session,
        )

    def _verdict(self, msg):
        doc = json.loads(msg.data)  # (a signature member, if any, is one more field)
        if doc.get("id"):
            self.verdicts[doc["id"]] = doc

    def publish(self, text):
        """Signed with this test's key when the suite runs enforced (and the text can be)."""
        try:
            text = self.security.sign("dsr/transactions", text)
        except ValueError:
            pass  # not a JSON object's text: sent as it is (and refused as not signed)
        self.pub.publish(String(data=text))

    def send(self, doc_or_text, ident, timeout=10):
        text = doc_or_text if isinstance(doc_or_text, str) else json.dumps(doc_or_text)
        self.publish(text)
        wait_for(lambda: ident in self.verdicts, timeout, f"a verdict on {ident}", self.ros.session)
        return self.verdicts[ident]


def start_server(ros, world, **params):
    ros.procs.start_server(ros.tmp / "state", world=world, **params)
    return snapshot_via(ros.session, timeout=20)


def text_op(text):
    return [{"op": "set_node_attrs", "node": "panel", "attrs": {"text": text}}]


def test_a_node_cannot_write_as_another_running_node(ros):
    start_server(ros, WORLD_CLARC)
    me = ros.session.node.get_fully_qualified_name()  # /test_client
    # the session's own topic: recorded as itself; claiming to be /speech is refused naming both
    own = Requests(ros, f"dsr/transactions/{ros.session.node.get_name()}")
    delta = own.send({"id": "a1", "ops": text_op("mine")}, "a1")
    assert delta["agent"] == me
    refused = own.send({"id": "a2", "agent": "/speech", "ops": text_op("x")}, "a2")
    assert refused["reason"]["rule"] == "identity"
    assert "/speech" in refused["error"] and me in refused["error"]
    # a real /speech runs; this node publishes on its topic too: refused, and an alarm names us
    speech = ros.procs.start("speech", ["speech"])
    wait_for(lambda: "agent up" in ros.procs.log("speech"), 30, "the speech agent")

    def described():  # its own info node written (model/agent_info.py): nothing more comes
        return any(n["name"] == "/speech" for n in snapshot_via(ros.session)["nodes"])

    wait_for(described, 30, "the speech agent's info node")
    before = snapshot_via(ros.session)
    spoof = Requests(ros, "dsr/transactions/speech")
    refused = spoof.send({"id": "s1", "ops": text_op("spoofed")}, "s1")
    assert refused["reason"]["rule"] == "identity" and me in refused["error"]
    wait_for(lambda: spoof.alarms, 10, "the alarm", ros.session)
    assert spoof.alarms[0]["intruders"] == [me] and spoof.alarms[0]["topic"].endswith("speech")
    after = snapshot_via(ros.session)
    assert after["seq"] == before["seq"] and canonical(after) == canonical(before)
    assert "refusing requests on /dsr/transactions/speech" in ros.procs.log("server")
    assert speech.poll() is None


def test_writes_outside_the_policy_are_refused_and_change_nothing(ros):
    policy = ros.tmp / "policy.yaml"
    policy.write_text(WORLD_POLICY)
    session = ros.session.node
    start_server(ros, WORLD_CLARC, policy_file=policy)
    assert "policy" in ros.procs.log("server") and "1 entries" in ros.procs.log("server")
    # this node is /test_client: no entry names it
    mine = Requests(ros, f"dsr/transactions/{session.get_name()}")
    before = snapshot_via(ros.session)
    refused = mine.send({"id": "p1", "ops": text_op("hello")}, "p1")
    assert refused["reason"]["rule"] == "policy" and "/test_client" in refused["error"]
    assert canonical(snapshot_via(ros.session)) == canonical(before)

    # /writer (a dsr apply renamed) may set the text, not delete a node or add an edge
    def apply(doc):
        return ros.procs.run(
            "dsr", "apply", "-", "--ros-args", "-r", "__node:=writer", input=json.dumps(doc)
        )

    assert apply({"ops": text_op("allowed")}).returncode == 0
    before = snapshot_via(ros.session)
    for doc, named in [
        ({"ops": [{"op": "delete_node", "node": "chair"}]}, "node type 'transform'"),
        (
            {
                "ops": text_op("y")
                + [{"op": "insert_edge", "from": "robot", "to": "panel", "type": "has"}]
            },
            "edge type 'has'",
        ),
        (
            {"ops": [{"op": "set_node_attrs", "node": "panel", "attrs": {"color": "Red"}}]},
            "'color'",
        ),
    ]:
        done = apply(doc)
        assert done.returncode == 1 and "policy" in done.stdout and named in done.stdout, (
            done.stdout
        )
        assert "'/writer'" in done.stdout
    assert canonical(snapshot_via(ros.session)) == canonical(before)


# --------------------------------------------------------------------------- hostile requests
JSON_LEAF = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(alphabet=st.characters(codec="utf-8"), max_size=40),
)
JSON = st.recursive(
    JSON_LEAF,
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=20,
)
GOOD_OP = {"op": "set_node_attrs", "node": "panel", "attrs": {"text": "ok"}}


@st.composite
def hostile(draw):
    """A request that must be refused: one good op spoiled in one way, or anything else."""
    kind = draw(
        st.sampled_from(
            ["wrong_type", "unknown_op", "unknown_field", "nan", "huge", "nested", "unicode", "any"]
        )
    )
    op = dict(GOOD_OP)
    if kind == "wrong_type":
        key = draw(st.sampled_from(["node", "attrs", "op"]))
        # (an integer is a node id, so a valid node reference: not among the wrong types)
        op[key] = draw(JSON.filter(lambda v: not isinstance(v, (str, dict)) and not _int(v)))
        return {"ops": [op]}
    if kind == "unknown_op":
        op["op"] = draw(st.text(min_size=1, max_size=20).filter(lambda s: not s.islower()))
        return {"ops": [op]}
    if kind == "unknown_field":
        name = draw(
            st.text(min_size=1, max_size=12).filter(lambda s: s not in ("op", "node", "attrs"))
        )
        op[name] = draw(JSON)
        return {"ops": [op], draw(st.sampled_from(["ops", "x-" + name])): [op]}
    if kind == "nan":
        op["attrs"] = {"text": draw(st.sampled_from([math.nan, math.inf, -math.inf]))}
        return {"ops": [op, {"op": "delete_node", "node": "nobody"}]}
    if kind == "huge":
        return {"ops": [dict(op, attrs={"text": "x" * 200_000})]}
    if kind == "nested":
        depth = draw(st.integers(min_value=50, max_value=5000))
        return '{"ops": [' + "[" * depth + "]" * depth + "]}"
    if kind == "unicode":
        name = draw(st.text(alphabet=st.characters(codec="utf-8"), min_size=1, max_size=10))
        return {"ops": [dict(op, node="\ud800" if draw(st.booleans()) else name + "\u202e")]}
    return draw(
        JSON.filter(lambda v: not isinstance(v, dict) or not {"ops", "claim", "release"} & set(v))
    )


def _int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def test_hostile_requests_leave_the_server_up_and_the_graph_unchanged(ros):
    start_server(ros, WORLD_CLARC, max_request_bytes=100_000)
    requests = Requests(ros, f"dsr/transactions/{ros.session.node.get_name()}")
    before = canonical(snapshot_via(ros.session))
    counter = iter(range(10**9))

    @settings(
        max_examples=150,
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    )
    @given(hostile())
    def one(doc):
        ident = f"h{next(counter)}"
        if isinstance(doc, dict):
            text = json.dumps({**doc, "id": ident}, allow_nan=True, ensure_ascii=False)
        else:  # not an object: the server cannot read an id from it; a marker follows
            text = doc if isinstance(doc, str) else json.dumps(doc, allow_nan=True)
        requests.publish(text.encode("utf-8", "surrogatepass").decode("utf-8", "replace"))
        marker = f"m{ident}"
        verdict = requests.send(
            {"id": marker, "ops": [{"op": "delete_node", "node": "nobody"}]}, marker
        )
        assert verdict["reason"]["rule"] == "node-missing"  # the server is up and answering
        if ident in requests.verdicts:  # (a request too large to read has no id to answer to)
            assert "reason" in requests.verdicts[ident], f"accepted: {text[:200]}"
        assert ros.procs.procs["server"].poll() is None

    one()
    assert canonical(snapshot_via(ros.session)) == before
