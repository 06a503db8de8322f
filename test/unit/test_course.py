"""The course of a test as observers read it from the DSR (clarc_agents/course.py): the steps of
a whole Barthel test with every deviation, an observer started in the middle of a test, and a
PELEA restarted in the middle, all read from the graph alone (test/local_clarc.py, no ROS)."""

from datetime import datetime

from clarc_agents.course import Course

from local_clarc import EVERY_PATH, Robot


def observe(robot, at: float = 0.0, since=None) -> list[dict]:
    """An observer joining at virtual time ``at``: its events as the test goes on."""
    events: list[dict] = []

    def join():
        link = robot.bus.agent("/observer")
        course = Course(since)
        events.extend(course.follow(link.graph))
        link.add_listener(lambda deltas, resynced: events.extend(course.follow(link.graph)))

    robot.bus.after(at, join) if at else join()
    return events


def steps(events, *kinds):
    return [
        (e["event"], e.get("item"), e.get("attempt") or e.get("points"))
        for e in events
        if e["event"] in kinds
    ]


def test_the_whole_course_of_a_test_with_every_deviation_is_read_from_the_dsr():
    robot = Robot(EVERY_PATH)
    events = observe(robot)
    result = robot.run_test()
    kinds = [e["event"] for e in events]
    assert kinds[0] == "started" and kinds[-1] == "finished"
    assert events[-1]["result"]["total"] == result["total"]
    assert [e["item"] for e in events if e["event"] == "item"] == [
        i["item"] for i in result["items"]
    ]
    answers = {e["item"]: (e["points"], e["via"]) for e in events if e["event"] == "answer"}
    assert answers == {i["item"]: (i["points"], i["via"]) for i in result["items"] if i["via"]}
    assert [e["item"] for e in events if e["event"] == "unanswered"] == result["unanswered"]
    assert steps(events, "listening", "no_answer", "not_understood", "skip", "unanswered")[2:] == [
        ("listening", "grooming", 1),
        ("no_answer", "grooming", 1),
        ("listening", "grooming", 2),
        ("no_answer", "grooming", 2),
        ("unanswered", "grooming", None),
        ("listening", "dressing", 1),
        ("not_understood", "dressing", 1),
        ("listening", "dressing", 2),
        ("listening", "bowels", 1),
        ("no_answer", "bowels", 1),
        ("listening", "bowels", 2),
        ("listening", "bladder", 1),
        ("skip", "bladder", 1),
        ("unanswered", "bladder", None),
        ("listening", "toilet_use", 1),
        ("listening", "transfers", 1),
        ("listening", "mobility", 1),
        ("listening", "stairs", 1),
    ]
    assert kinds.count("person_lost") == kinds.count("person_back") == 1
    assert kinds.count("clinician_called") == 1  # grooming and bladder unanswered
    assert (
        next(e for e in events if e["event"] == "not_understood")["heard"]
        == robot.pelea_link.graph.node("item_dressing").attrs["heard"]
    )
    # everything PELEA told of the answers, the observer read from the DSR
    told = [(e["item"], e["points"]) for e in robot.port.events if e["event"] == "answer"]
    assert told == [(e["item"], e["points"]) for e in events if e["event"] == "answer"]


def test_an_observer_started_mid_test_says_where_the_test_is_then_follows_it():
    probe = Robot(EVERY_PATH)
    probe.run_test()
    middle = next(e["t"] for e in probe.port.events if e["event"] == "listening") + 0.1
    robot = Robot(EVERY_PATH)
    events = observe(robot, at=middle)
    result = robot.run_test()
    assert events[0]["event"] == "following" and events[0]["item"] == "feeding"
    assert "started" not in [e["event"] for e in events]
    answered = [e["item"] for e in events if e["event"] == "answer"]
    assert answered == [i["item"] for i in result["items"] if i["via"]]  # feeding included


def test_a_pelea_restart_is_told_as_an_interrupted_window_and_nothing_is_repeated():
    probe = Robot(EVERY_PATH)
    probe.run_test()
    opened = [e["t"] for e in probe.port.events if e["event"] == "listening"][3]
    robot = Robot(EVERY_PATH)
    events = observe(robot)
    robot.bus.after(opened + 0.2, robot.restart_pelea)
    result = robot.run_test()
    interrupted = [e for e in events if e["event"] == "window_interrupted"]
    assert len(interrupted) == 1
    answers = [e["item"] for e in events if e["event"] == "answer"]
    assert answers == [i["item"] for i in result["items"] if i["via"]]  # each told once
    assert [e["event"] for e in events].count("started") == 1


def test_an_observer_started_for_a_test_under_way_tells_it_from_its_start():
    probe = Robot(EVERY_PATH)
    probe.run_test()
    later = [e["t"] for e in probe.port.events if e["event"] == "listening"][4] + 0.1
    robot = Robot(EVERY_PATH)
    since = datetime.fromisoformat(robot.port.now())  # before Start: the observer's test
    events = observe(robot, at=later, since=since)
    result = robot.run_test()
    assert events[0]["event"] == "started" and events[-1]["event"] == "finished"
    answered = [e["item"] for e in events if e["event"] == "answer"]
    assert answered == [i["item"] for i in result["items"] if i["via"]]
    assert "following" not in [e["event"] for e in events]
    # every item it passed is told, in order, each before what happened in it
    told = [e["item"] for e in events if e["event"] == "item"]
    assert told == [i["item"] for i in result["items"]]
    reached: list[str] = []
    for e in events:
        if e["event"] == "item":
            reached.append(e["item"])
        elif e["event"] in ("answer", "no_answer", "unanswered"):
            assert e["item"] in reached, e
