"""protocol/cut_off.py: an agent whose own ends of the link stay unmatched asks a probe, no sooner
than CUT_OFF_AFTER and no more often than PROBE_EVERY, and is cut off only when the probe sees
the server while its own ends are still unmatched."""

from dsr_graph.protocol.cut_off import (
    CUT_OFF_AFTER,
    LOOK_EVERY,
    PROBE_AT_MOST,
    PROBE_EVERY,
    CutOffWatch,
)


def test_a_matched_link_never_asks_a_probe():
    watch = CutOffWatch()
    assert not any(watch.look(True, t) for t in range(100))


def test_a_link_unmatched_as_long_as_a_restart_takes_asks_no_probe():
    watch = CutOffWatch()
    assert not watch.look(False, 0.0)
    assert not watch.look(False, CUT_OFF_AFTER - 0.1)
    assert not watch.look(True, CUT_OFF_AFTER + 0.1)  # the server is back
    assert not watch.look(False, CUT_OFF_AFTER + 0.2)  # unmatched again: counted anew


def test_a_link_unmatched_long_enough_asks_one_probe_at_a_time():
    watch = CutOffWatch()
    watch.look(False, 0.0)
    assert watch.look(False, CUT_OFF_AFTER)
    assert not watch.look(False, CUT_OFF_AFTER + PROBE_EVERY + 1)  # the first still runs
    assert not watch.probed(server_seen=False, matched_now=False)  # the server is down
    assert not watch.look(False, CUT_OFF_AFTER + PROBE_EVERY - 0.1)
    assert watch.look(False, CUT_OFF_AFTER + PROBE_EVERY)


def test_a_server_that_stays_down_is_probed_less_and_less_often():
    watch, now, gaps = CutOffWatch(), 0.0, []
    watch.look(False, now)
    last = None
    while now < 1000:
        now += 0.5
        if watch.look(False, now):
            if last is not None:
                gaps.append(now - last)
            last = now
            assert not watch.probed(server_seen=False, matched_now=False)
    assert gaps[:5] == [PROBE_EVERY, 2 * PROBE_EVERY, 4 * PROBE_EVERY, PROBE_AT_MOST, PROBE_AT_MOST]
    watch.look(True, now)  # the server is back: the next outage starts over
    assert watch.every == PROBE_EVERY


def test_cut_off_only_when_the_probe_sees_the_server_and_the_link_is_still_unmatched():
    watch = CutOffWatch()
    watch.look(False, 0.0)
    assert watch.look(False, CUT_OFF_AFTER)
    assert not watch.probed(server_seen=True, matched_now=True)  # matched meanwhile
    assert watch.unmatched_since is None
    watch.look(False, 100.0)
    assert watch.look(False, 100.0 + CUT_OFF_AFTER)
    assert watch.probed(server_seen=True, matched_now=False)


def test_the_link_is_looked_at_once_a_second():
    watch = CutOffWatch()
    assert watch.due_look(0.0)
    assert not watch.due_look(LOOK_EVERY - 0.01)
    assert watch.due_look(LOOK_EVERY)
