"""The monitor's view of reach (clarc_sim/console/reach.py): nodes leaving and rejoining the ROS
graph, and the DSR server's heartbeat going silent and coming back."""

from clarc_sim.console.reach import HeartbeatSilence, Reach, where_agents_stand


def test_a_node_seen_then_unlisted_is_out_of_reach_until_listed_again():
    reach = Reach(["/speech", "/panel", "/pelea"])
    assert reach.update(["/speech", "/panel", "/viewer"]) == []  # first seen: nothing to say
    assert reach.update(["/panel"]) == ["out of reach: /speech"]
    assert reach.update(["/panel"]) == []  # said once
    assert reach.update([]) == ["out of reach: /panel"]
    assert reach.update(["/speech", "/panel", "/pelea"]) == ["back in reach: /panel, /speech"]


def test_a_node_never_seen_or_not_watched_is_never_reported():
    reach = Reach(["/pelea"])
    assert reach.update(["/viewer"]) == [] and reach.update([]) == []


def test_the_heartbeat_going_silent_and_back_is_said_once_each():
    silence = HeartbeatSilence(2.5)
    assert silence.update(None, 10.0) is None  # never heard
    assert silence.update(10.0, 11.0) is None
    assert silence.update(10.0, 13.0) == "the DSR server is out of reach (no heartbeat for 3.0 s)"
    assert silence.update(10.0, 14.0) is None
    assert silence.update(16.0, 16.1) == "the DSR server is back in reach after 6.0 s"
    assert silence.update(16.5, 16.6) is None


def test_a_test_that_did_not_finish_says_each_agents_state_and_the_nodes_that_never_joined():
    agents = [
        {"name": "/panel", "state": "starting", "pid": 41},
        {"name": "/speech", "state": "ready", "pid": 42},
        {"name": "/pelea", "state": ""},
    ]
    line = where_agents_stand(agents, ["/panel", "/speech", "/camera", "/dsr_server"])
    assert line == (
        "agents as the DSR shows them: /panel starting (pid 41), /speech ready (pid 42), "
        "/pelea ?; ROS nodes with no agent info: /camera, /dsr_server"
    )
    assert where_agents_stand([], []).endswith("them: none; ROS nodes with no agent info: none")
