"""protocol/absence.py: when the server ends a gone agent's claims and marks its info node."""

from dsr_graph.protocol.absence import Absences

WAITS = {"grace": 10.0, "info_grace": 2.0}


def test_an_agent_that_left_is_marked_gone_first_and_loses_its_claims_later():
    absences = Absences()
    ask = lambda now, live=(): absences.update(  # noqa: E731
        {"/speech"}, {"/speech"}, live, now, warm=True, **WAITS
    )
    assert ask(0.0) == ([], [])
    assert ask(1.9) == ([], [])
    assert ask(2.0) == ([], ["/speech"])
    assert ask(10.0) == (["/speech"], ["/speech"])
    # told once: its absence starts again
    assert ask(11.0) == ([], [])


def test_an_agent_seen_again_starts_its_wait_again():
    absences = Absences()
    assert absences.update(set(), {"/panel"}, [], 0.0, warm=True, **WAITS) == ([], [])
    assert absences.update(set(), {"/panel"}, ["/panel"], 1.5, warm=True, **WAITS) == ([], [])
    assert absences.update(set(), {"/panel"}, [], 3.0, warm=True, **WAITS) == ([], [])
    assert absences.update(set(), {"/panel"}, [], 5.0, warm=True, **WAITS) == ([], ["/panel"])


def test_no_info_node_is_marked_while_the_server_warms_up():
    absences = Absences()
    for now in (0.0, 2.5, 9.0):
        assert absences.update(set(), {"/person"}, [], now, warm=False, **WAITS) == ([], [])
    assert absences.update(set(), {"/person"}, [], 9.5, warm=True, **WAITS) == ([], ["/person"])


def test_an_agent_no_longer_watched_is_forgotten():
    absences = Absences()
    absences.update({"/pelea"}, set(), [], 0.0, warm=True, **WAITS)
    absences.update(set(), set(), [], 5.0, warm=True, **WAITS)  # its claims ended otherwise
    assert absences.update({"/pelea"}, set(), [], 6.0, warm=True, **WAITS) == ([], [])
    assert absences.update({"/pelea"}, set(), [], 16.0, warm=True, **WAITS) == (["/pelea"], [])
