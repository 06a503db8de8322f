"""Reach across a network cut: who the server can hear (protocol/presence.py, from DDS
liveliness), and an answer given in a cut kept until the link is back (early_answer.py)."""

from clarc_agents.behaviours.early_answer import NO_GAP, EarlyAnswer
from dsr_graph.protocol.presence import Presence


def test_an_agent_matched_but_not_alive_is_out_of_reach_until_alive_again():
    presence = Presence()
    presence.observe("/dsr/transactions/speech", "/speech", alive=1, not_alive=0)
    assert presence.update(10.0) == ([], []) and presence.away == []
    presence.observe("/dsr/transactions/speech", "/speech", alive=0, not_alive=1)
    assert presence.update(11.0) == (["/speech"], [])
    assert presence.update(12.0) == ([], [])  # told once
    assert presence.away == ["/speech"]
    presence.observe("/dsr/transactions/speech", "/speech", alive=1, not_alive=0)
    assert presence.update(16.5) == ([], [("/speech", 5.5)])
    assert presence.away == []


def test_a_publisher_no_longer_matched_is_gone_not_out_of_reach():
    # DDS dropped the participant (its lease ran out, or it exited): the agent_grace of the
    # server's ROS graph check handles it
    presence = Presence()
    presence.observe("/dsr/transactions/panel", "/panel", alive=0, not_alive=1)
    presence.update(1.0)
    presence.observe("/dsr/transactions/panel", "/panel", alive=0, not_alive=0)
    assert presence.update(3.0) == ([], [("/panel", 2.0)])
    assert presence.away == []


def test_a_restarted_agent_alive_next_to_its_lapsed_ghost_is_in_reach():
    presence = Presence()
    presence.observe("/dsr/transactions/speech", "/speech", alive=1, not_alive=1)
    assert presence.update(1.0) == ([], []) and presence.away == []


def test_a_process_killed_after_its_successor_was_up_is_told_ended_once():
    """Respawned at once, the successor is alive before its predecessor's lease runs out: the
    agent is never out of reach, and the end of the old process is told all the same."""
    presence = Presence()
    topic = "/dsr/transactions/panel"
    presence.observe(topic, "/panel", alive=1, not_alive=0)
    presence.observe(topic, "/panel", alive=2, not_alive=0)  # the successor, up at once
    assert presence.take_ended() == []
    presence.observe(topic, "/panel", alive=1, not_alive=1)  # the old one's lease ran out
    assert presence.update(1.0) == ([], []) and presence.away == []
    assert presence.take_ended() == ["/panel"]
    assert presence.take_ended() == []  # told once
    presence.observe(topic, "/panel", alive=1, not_alive=0)  # its participant dropped
    assert presence.take_ended() == []


def test_an_answer_given_in_a_cut_waits_for_the_link_to_come_back():
    # Speech and Panel keep an answer given before its window opened for PATIENCE seconds once
    # the robot has begun another sentence; in a network cut that moment counts from when the
    # server is heard again.
    clock = [0.0]
    gap = [NO_GAP]
    early = EarlyAnswer(lambda: clock[0], lambda: gap[0])
    early.keep(10, "bathing")
    early.asked()  # the patient answered while the options were read; the request followed
    clock[0] = 6.0  # the heartbeat was last heard at 0.5 and came back at 5.5
    gap[0] = (0.5, 5.5)
    assert early.take("bathing") == 10
    early.keep(10, "bathing")
    early.asked()
    clock[0] = 9.0  # no cut since: 3 s is too late
    assert early.take("bathing") is None


def test_an_answer_stale_before_the_cut_stays_stale():
    clock, early = [30.0], EarlyAnswer(lambda: 30.0, lambda: (20.0, 29.5))
    early.keep(5, "stairs")  # kept at 30... after the gap: the usual patience
    early.asked()
    assert early.take("stairs") == 5
    early = EarlyAnswer(lambda: clock[0], lambda: (20.0, 29.5))
    clock[0] = 10.0
    early.keep(5, "stairs")  # 10 s before the link went down
    early.asked()
    clock[0] = 30.0
    assert early.take("stairs") is None
    early.keep(5, "feeding")
    assert early.take("stairs") is None  # another item's answer is never taken


def test_an_answer_to_the_last_sentence_waits_for_a_window_held_after_it():
    # a chaos run: the options said again, the patient answered at once, and PELEA held the
    # window 4 s for a restarting Panel; the answer is to that sentence however late it opens
    clock = [0.0]
    early = EarlyAnswer(lambda: clock[0])
    early.asked()  # "Let me say the options again..."
    clock[0] = 1.0
    early.keep("I need some help", "dressing")
    clock[0] = 60.0  # held for a minute, nothing said meanwhile
    assert early.take("dressing") == "I need some help"
    assert early.take("dressing") is None  # taken once
    early.keep("I need some help", "dressing")
    early.asked()  # the robot began another sentence: only the moment counts now
    clock[0] = 63.0
    assert early.take("dressing") is None
    early.keep("two", "dressing")
    assert early.take("bathing") is None  # another item's window drops it
    assert early.take("dressing") is None
    # an agent that never sees the robot's sentences (Person's eyes): the moment alone counts
    early = EarlyAnswer(lambda: clock[0])
    early.keep(1, "reading")
    clock[0] = 70.0
    assert early.take("reading") is None


def test_an_agent_whose_request_publisher_is_alive_is_not_gone_whatever_the_ros_graph_lists():
    from dsr_graph.protocol.absence import Absences

    presence = Presence()
    presence.observe("/dsr/transactions/panel", "/panel", alive=1, not_alive=0)
    presence.observe("/dsr/transactions/speech", "/speech", alive=0, not_alive=1)  # killed
    assert presence.alive == {"/panel"}
    # the ROS graph lists neither (a loaded machine's discovery, for minutes): only the agent
    # whose process ended is marked gone, as the server composes them (ros/server_node.py)
    absences = Absences()
    for now in (10.0, 13.0):
        claims, info = absences.update(
            set(), {"/panel", "/speech"}, presence.alive, now, grace=5, info_grace=2, warm=True
        )
    assert info == ["/speech"] and claims == []


def test_a_killed_process_dropped_without_lapsing_is_told_ended_too():
    """DDS may unmatch a killed process's publisher without counting it not alive first (a
    loaded whole-suite run: Panel killed and respawned, its end never told, the test waited for
    "gone" 30 s): one alive fewer, none lapsed, is the same end."""
    presence = Presence()
    topic = "/dsr/transactions/panel"
    presence.observe(topic, "/panel", alive=1, not_alive=0)
    presence.observe(topic, "/panel", alive=2, not_alive=0)  # the successor, up at once
    presence.observe(topic, "/panel", alive=1, not_alive=0)  # the old one unmatched
    assert presence.update(1.0) == ([], []) and presence.away == []
    assert presence.take_ended() == ["/panel"]
    presence.observe(topic, "/panel", alive=0, not_alive=0)  # the last one stopped
    assert presence.take_ended() == ["/panel"]
    assert presence.update(2.0) == ([], []) and presence.away == []


def test_a_lapse_and_a_drop_read_as_one_event_are_an_end_not_a_cut():
    """A server starved for a second or more reads the liveliness counts as they are then: the
    killed process's lapse and its participant's drop come as one change (1 alive -> none, none
    lapsed). Its end is told at once, before a successor respawned within the ROS graph's grace
    could hide it (a fresh-clone run: "timed out after 30 s waiting for panel gone", the server
    logged nothing)."""
    presence = Presence()
    topic = "/dsr/transactions/panel"
    presence.observe(topic, "/panel", alive=1, not_alive=0)
    presence.observe(topic, "/panel", alive=0, not_alive=0)
    assert presence.take_ended() == ["/panel"]
    assert presence.update(1.0) == ([], [])  # never out of reach: gone
    presence.observe(topic, "/panel", alive=1, not_alive=0)  # the successor
    assert presence.take_ended() == [] and presence.alive == {"/panel"}


def test_a_lapsed_publisher_dropped_later_is_told_once_as_out_of_reach():
    # a network cut: the lapse comes first (out of reach, its info node gone), then DDS drops
    # the participant: nothing more to tell
    presence = Presence()
    topic = "/dsr/transactions/speech"
    presence.observe(topic, "/speech", alive=1, not_alive=0)
    presence.observe(topic, "/speech", alive=0, not_alive=1)
    assert presence.update(1.0) == (["/speech"], []) and presence.take_ended() == []
    presence.observe(topic, "/speech", alive=0, not_alive=0)
    assert presence.take_ended() == []
