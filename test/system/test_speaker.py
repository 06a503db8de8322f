"""The simulated speaker (clarc_sim's tts node): a sentence said again while it is being said
goes on, as Speech's retry of a start it did not hear in time must not cut it."""

import json

from std_msgs.msg import String

from clarc_agents import topics
from dsr_graph.ros.qos import qos_stream

from ros_processes import wait_for


def test_a_sentence_said_again_while_it_is_said_goes_on_and_ends_once(ros):
    events = []
    node = ros.session.node
    node.create_subscription(
        String, topics.SPEAKER, lambda m: events.append(json.loads(m.data)), qos_stream()
    )
    say = node.create_publisher(String, topics.SPEAKER_SAY, qos_stream())
    ros.procs.start("tts", ["tts", "--ros-args", "-p", "time_scale:=0.2"])
    wait_for(lambda: say.get_subscription_count() > 0, 30, "the speaker", ros.session)

    def said(sid, text):
        say.publish(String(data=json.dumps({"id": sid, "text": text})))

    said(1, "Let me say the options again. Option one, option two, option three.")
    wait_for(lambda: events, 10, "the sentence's start", ros.session)
    said(1, "Let me say the options again. Option one, option two, option three.")  # a retry
    wait_for(lambda: any(e["event"] == "end" for e in events), 20, "its end", ros.session)
    assert [e["event"] for e in events if e["id"] == 1] == ["start", "start", "end"]
    said(2, "Another sentence.")  # another sentence still cuts the one being said
    said(3, "And another.")
    wait_for(lambda: any(e["id"] == 3 for e in events), 10, "the third", ros.session)
    wait_for(lambda: any(e["event"] == "end" for e in events[3:]), 20, "its end", ros.session)
    assert [(e["id"], e["event"]) for e in events[3:]] == [
        (2, "start"),
        (2, "stopped"),
        (3, "start"),
        (3, "end"),
    ]
