"""The rule runner (the paper's Algorithm 2) with no ROS: agents on a LocalBus, each running
declared rules; before -> during (compare-and-set) -> process -> after, races, percepts, claims."""

import logging

import pytest

from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import Policy
from dsr_graph.protocol.local_bus import LocalBus
from dsr_graph.rules.runner import RuleRunner
from dsr_graph.rules.syntax import load_rules

log = logging.getLogger("test_rule_runner")

SPEAK = {
    "name": "speak",
    "when": [
        {"edge": ["robot", "speaking", "is_not"]},
        {"edge": ["test", "test_part", "is_in"], "attrs": {"text": "$text", "sentence_id": "$sid"}},
    ],
    "once_per": ["$sid"],
    "during": [
        {"delete_edge": ["robot", "speaking", "is_not"]},
        {"insert_edge": ["robot", "speaking", "is"]},
    ],
    "claim": [{"from": "robot", "to": "speaking"}],
    "process": "say",
    "after": {
        "done": [
            {"delete_edge": ["robot", "speaking", "is"]},
            {"insert_edge": ["robot", "speaking", "finish", {"sentence_id": "$sid"}]},
        ],
        "interrupted": [
            {"delete_edge": ["robot", "speaking", "is"]},
            {"insert_edge": ["robot", "speaking", "is_not"]},
        ],
    },
}
SEEN = {
    "name": "seen",
    "trigger": "seen",
    "given": ["$pose"],
    "when": [{"no_node": "person"}],
    "during": [
        {"insert_node": {"name": "person", "type": "person"}},
        {"insert_edge": {"from": "robot", "to": "person", "type": "RT", "rt": "$pose"}},
    ],
}
POSE = {"translation": [1.0, 2.0, 0.0], "rotation_euler_xyz": [0.0, 0.0, 0.0]}


def world():
    g = Graph()
    with g.atomic():
        for name, kind in [
            ("world", "transform"),
            ("robot", "robot"),
            ("speaking", "state"),
            ("test", "test"),
            ("test_part", "test_part"),
        ]:
            g.insert_node(name, kind)
        g.insert_edge(
            "world", "robot", "RT", rt={"translation": [0, 0, 0], "rotation_euler_xyz": [0, 0, 0]}
        )
        g.insert_edge("robot", "speaking", "is_not")
    return g


def write_sentence(bus, sid, text="Hello"):
    writer = bus.agents[0] if bus.agents else bus.agent("/pelea")
    op = (
        "insert_edge"
        if bus.core.graph.edge("test", "test_part", "is_in") is None
        else "set_edge_attrs"
    )
    writer.send(
        {
            "ops": [
                {
                    "op": op,
                    "from": "test",
                    "to": "test_part",
                    "type": "is_in",
                    "attrs": {"text": text, "sentence_id": sid},
                }
            ]
        }
    )


class Speaker:
    """A ``say`` process that finishes when the test says so."""

    def __init__(self):
        self.saying = []

    def say(self, ctx):
        self.saying.append(ctx)


def speech_agent(bus, name="/speech", rules=(SPEAK,), speaker=None):
    speaker = speaker or Speaker()
    runner = RuleRunner(bus.agent(name), load_rules(list(rules)), {"say": speaker.say}, log)
    runner.setup()
    return runner, speaker


def edges_from_robot_to_speaking(bus):
    return sorted(
        e.type
        for e in bus.core.graph.out_edges("robot")
        if e.dst == bus.core.graph.node("speaking").id
    )


def test_before_during_process_after():
    bus = LocalBus(world())
    pelea = bus.agent("/pelea")
    runner, speaker = speech_agent(bus)
    write_sentence(bus, 1, "Hello Carlos")
    bus.run()
    assert [c["text"] for c in speaker.saying] == ["Hello Carlos"]
    assert edges_from_robot_to_speaking(bus) == ["is"]  # during: the robot is speaking
    assert bus.core.claims.held_by("/speech")  # and holds its claim while it speaks
    speaker.saying[0].finish("done")
    bus.run()
    assert edges_from_robot_to_speaking(bus) == ["finish"]
    assert bus.core.graph.edge("robot", "speaking", "finish").attrs == {"sentence_id": 1}
    assert not bus.core.claims.held_by("/speech")  # released with the after write
    assert runner.fired == 1 and not runner.running
    assert pelea.graph.edge("robot", "speaking", "finish") is not None  # every replica saw it


def test_once_per_fires_again_only_for_a_new_sentence():
    bus = LocalBus(world())
    bus.agent("/pelea")
    runner, speaker = speech_agent(bus)
    write_sentence(bus, 1)
    bus.run()
    speaker.saying[0].finish("interrupted")  # back to robot is_not speaking, sentence unchanged
    bus.run()
    assert len(speaker.saying) == 1, "the same sentence must not be said twice"
    write_sentence(bus, 2, "Bye")
    bus.run()
    assert [c["text"] for c in speaker.saying] == ["Hello", "Bye"]


def test_two_agents_race_for_one_action_and_exactly_one_takes_it():
    bus = LocalBus(world())
    bus.agent("/pelea")
    first, a = speech_agent(bus, "/speech_a")
    second, b = speech_agent(bus, "/speech_b")
    write_sentence(bus, 1)
    bus.run()
    assert len(a.saying) + len(b.saying) == 1
    assert first.fired + second.fired == 1 and first.lost + second.lost == 1


def test_a_percept_enters_only_while_its_pattern_holds():
    bus = LocalBus(world())
    runner = RuleRunner(bus.agent("/person"), load_rules([SEEN]), {}, log)
    runner.setup()
    assert runner.signal("seen", pose=POSE) == 1
    bus.run()
    assert bus.core.graph.node("person").type == "person"
    assert bus.core.graph.transform("world", "person")[0, 3] == pytest.approx(1.0)
    assert runner.signal("seen", pose=POSE) == 0  # no_node: person no longer holds


def test_a_racing_percept_is_refused_by_the_server_not_applied_twice():
    bus = LocalBus(world())
    runner = RuleRunner(bus.agent("/person"), load_rules([SEEN]), {}, log)
    runner.setup()
    assert runner.signal("seen", pose=POSE) == 1
    assert runner.signal("seen", pose=POSE) == 1  # the replica has not seen the first one yet
    bus.run()
    assert bus.core.seq == 1 and len(bus.core.graph) == 6


PRIORITIES = Policy.from_doc(
    {
        "version": 1,
        "agents": [
            {"name": "/urgent", "priority": 5, "edges": ["*"]},
            {"name": "/speech", "priority": 1, "edges": ["*"], "attributes": ["*"]},
            {"name": "*", "priority": 0, "nodes": ["*"], "edges": ["*"], "attributes": ["*"]},
        ],
    }
)


def test_a_higher_priority_preempts_and_the_holder_is_told():
    bus = LocalBus(world(), policy=PRIORITIES)
    bus.agent("/pelea")
    runner, speaker = speech_agent(bus)
    told = []
    write_sentence(bus, 1)
    bus.run()
    speaker.saying[0].on_preempted = lambda: told.append(True)
    urgent = bus.agent("/urgent")
    verdicts = []
    urgent.send(
        {
            "priority": 0,  # ignored: the policy gives /urgent priority 5
            "ops": [
                {"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is"},
                {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
            ],
        },
        verdicts.append,
    )
    bus.run()
    assert verdicts[0].accepted and told == [True] and speaker.saying[0].preempted
    speaker.saying[0].finish("done")  # its after no longer applies: the during state was undone
    bus.run()
    assert edges_from_robot_to_speaking(bus) == ["is_not"]


def test_a_lower_priority_write_is_refused_while_the_claim_is_held():
    bus = LocalBus(world())
    bus.agent("/pelea")
    speech_agent(bus)
    write_sentence(bus, 1)
    bus.run()
    verdicts = []
    bus.agent("/other").send(
        {"ops": [{"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is"}]},
        verdicts.append,
    )
    bus.run()
    assert not verdicts[0].accepted and verdicts[0].reason["rule"] == "claimed"


def test_a_failing_process_ends_as_failed_and_the_agent_goes_on():
    bus = LocalBus(world())
    bus.agent("/pelea")
    calls = []

    def say(ctx):
        calls.append(ctx["text"])
        if len(calls) == 1:
            raise RuntimeError("speaker unplugged")
        return "done"

    rule = dict(SPEAK, after=dict(SPEAK["after"], failed=SPEAK["after"]["interrupted"]))
    runner = RuleRunner(bus.agent("/speech"), load_rules([rule]), {"say": say}, log)
    runner.setup()
    write_sentence(bus, 1)
    bus.run()
    assert edges_from_robot_to_speaking(bus) == ["is_not"]  # the "failed" after ran
    write_sentence(bus, 2, "Again")
    bus.run()
    assert calls == ["Hello", "Again"] and edges_from_robot_to_speaking(bus) == ["finish"]


def test_a_rule_naming_a_process_the_agent_lacks_is_refused_at_start():
    bus = LocalBus(world())
    with pytest.raises(ValueError, match="say"):
        RuleRunner(bus.agent("/speech"), load_rules([SPEAK]), {}, log)
