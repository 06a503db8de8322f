"""PELEA's High Level Executive against a local graph, no ROS: the whole Barthel test with Speech,
Panel and Person's real grammars and processes on a LocalBus (test/local_clarc.py), every
deviation and the replan it causes, and its action table against the PDDL domain."""

import contextlib
from pathlib import Path

import pytest
from barthel_items import BY_KEY, ORDER
from pyperplan.pddl.parser import Parser

from clarc_agents.pelea.decision_support import domain_path
from clarc_agents.pelea.questionnaire_executive import QuestionnaireExecutive
from clarc_agents.test_node import request_start
from dsr_graph.exceptions import TimedOutError

from local_clarc import EVERY_PATH, Patient, Robot

REPO = Path(__file__).resolve().parents[2]


def replans(robot):
    return [e["reason"] for e in robot.port.events if e["event"] == "plan"]


def items(result):
    return {i["item"]: (i["points"], i["via"], i["attempts"]) for i in result["items"]}


def test_every_action_of_the_domain_has_a_handler_and_no_handler_is_extra():
    parser = Parser(domain_path("questionnaire"))
    domain = parser.parse_domain()
    assert set(QuestionnaireExecutive.ACTIONS) == set(domain.actions)
    for name, action in domain.actions.items():  # each handler takes the action's parameters
        code = QuestionnaireExecutive.ACTIONS[name].__code__
        assert code.co_argcount == 2 + len(action.signature), name


def test_a_test_without_deviations():
    robot = Robot()
    result = robot.run_test()
    assert result["total"] == 100 and result["band"] == "independent"
    assert all(i["via"] == "voice" and i["attempts"] == 1 for i in result["items"])
    assert replans(robot) == ["start"]
    assert robot.said[0].startswith("Hello Carlos") and robot.said[-1].startswith(
        "That was the last question"
    )
    introduced = [s for s in robot.said if s.startswith("Question ")]
    assert introduced == [
        f"Question {n} of 10, {BY_KEY[i].title}. {BY_KEY[i].question}"
        for n, i in enumerate(ORDER, 1)
    ]
    test = robot.pelea_link.graph.node("test")
    assert test.attrs["status"] == "finished" and test.attrs["patient"] == "Carlos"


def test_silence_then_the_options_again_by_voice_and_on_the_screen():
    robot = Robot(Patient(answers={"feeding": ["silence", ("voice", 5)]}))
    result = robot.run_test()
    assert items(result)["feeding"] == (5, "voice", 2)
    assert replans(robot) == ["start", "deviation in (await-answer feeding)"]
    again = [
        s for s in robot.screen if s.get("text", "").startswith("Let me say the options again")
    ]
    assert again and again[0]["option_points"] == [0.0, 5.0, 10.0]


def test_silence_twice_leaves_the_item_unanswered_and_goes_on():
    robot = Robot(Patient(answers={"bathing": ["silence", "silence"]}))
    result = robot.run_test()
    assert items(result)["bathing"] == (None, None, 2)
    assert result["unanswered"] == ["bathing"] and not result["clinician_called"]
    assert "deviation in (await-answer-again bathing)" in replans(robot)
    assert items(result)["grooming"] == (5, "voice", 1)  # the next item is asked as usual


def test_words_not_understood_then_a_clarification_and_a_touch():
    robot = Robot(Patient(answers={"dressing": ["garbled", ("touch", 5)]}))
    result = robot.run_test()
    assert items(result)["dressing"] == (5, "touch", 2)
    assert any(s.startswith("Sorry, I did not understand.") for s in robot.said)
    not_understood = [e for e in robot.port.events if e["event"] == "not_understood"]
    assert not_understood[0]["heard"].startswith("mmh")


def test_words_never_understood_leave_the_item_to_the_clinician_with_its_clips():
    """Never a confident wrong score: an item the robot could not understand twice is no 0
    points but the clinician's to score, from what was heard and the clips; the result has no
    band until then, only the range the total lies in."""
    from clarc_sim.hospital.result_checks import check_result

    robot = Robot(Patient(answers={"bathing": ["garbled", "garbled"]}))
    result = robot.run_test()
    bathing = next(i for i in result["items"] if i["item"] == "bathing")
    assert (bathing["points"], bathing["via"], bathing["needs_clinician"]) == (None, None, True)
    assert bathing["audio"] == ["clips/bathing-1.wav", "clips/bathing-2.wav"]
    assert bathing["heard"].startswith("mmh")
    assert result["provisional"] and result["band"] is None and not result["complete"]
    assert result["total_range"] == [result["total"], result["total"] + 5]
    assert robot.port.stored  # CGAmed took it as it is
    check_result(result)
    # an item answered in the end, after words not understood, is no doubt
    robot = Robot(Patient(answers={"dressing": ["garbled", ("touch", 5)]}))
    result = robot.run_test()
    assert not result["provisional"] and result["band"] is not None
    dressing = next(i for i in result["items"] if i["item"] == "dressing")
    assert not dressing["needs_clinician"] and dressing["audio"] == ["clips/dressing-1.wav"]


def test_a_long_answer_keeps_its_window_open_until_its_words_are_heard():
    """The patient began to speak within the window (the asr's voice event, marked on the
    window by Speech) and the words are heard 12 s later, past the window's 8 s: answered, on
    the first try. A voice that never brings words is waited for a bounded time only."""
    robot = Robot(Patient(answers={"feeding": [("long", 10, 12.0)]}))
    result = robot.run_test()
    assert items(result)["feeding"] == (10, "voice", 1)
    robot = Robot(Patient(answers={"feeding": [("long", 10, 100.0), ("voice", 10)]}))
    result = robot.run_test()
    assert items(result)["feeding"] == (10, "voice", 2)  # asked again after the patience


def test_an_option_heard_not_for_sure_is_confirmed_by_voice_or_touch_once():
    """ "I heard: I eat by myself. Is that right?": yes, and the option counts (by voice, one
    try); no, and the item is asked again as for words not understood; asked once an item."""
    robot = Robot(Patient(answers={"feeding": [("unsure", 10)]}))
    result = robot.run_test()
    assert items(result)["feeding"] == (10, "voice", 1)
    assert "I heard: I eat by myself. Is that right?" in " ".join(robot.said)
    asked = next(s for s in robot.screen if s.get("text", "").startswith("I heard:"))
    assert asked["options"] == ["Yes", "No"]
    robot = Robot(Patient(answers={"feeding": [("unsure", 5)]}, confirms=["tap"]))
    assert items(robot.run_test())["feeding"] == (5, "voice", 1)  # yes on the screen
    robot = Robot(Patient(answers={"feeding": [("unsure", 10), ("voice", 5)]}, confirms=["no"]))
    result = robot.run_test()
    assert items(result)["feeding"] == (5, "voice", 2)
    assert any(s.startswith("Sorry, I did not understand.") for s in robot.said)
    # no yes twice: confirmed once only, then the clinician's, with what was heard
    patient = Patient(answers={"feeding": [("unsure", 10), ("unsure", 10)]}, confirms=["silence"])
    result = Robot(patient).run_test()
    feeding = next(i for i in result["items"] if i["item"] == "feeding")
    assert (feeding["points"], feeding["needs_clinician"]) == (None, True)
    assert result["provisional"] and result["band"] is None


def test_asking_to_skip_closes_the_item_at_once():
    robot = Robot(Patient(answers={"bowels": ["skip"]}))
    result = robot.run_test()
    assert items(result)["bowels"] == (None, None, 1)
    assert replans(robot)[1] == "deviation in (await-answer bowels)"


def test_two_unanswered_items_call_the_clinician_once():
    robot = Robot(
        Patient(
            answers={"grooming": ["silence", "silence"], "bowels": ["skip"], "stairs": ["skip"]}
        )
    )
    result = robot.run_test()
    assert result["unanswered"] == ["grooming", "bowels", "stairs"] and result["clinician_called"]
    assert len(robot.port.notifications) == 1 and "grooming, bowels" in robot.port.notifications[0]
    assert "two items unanswered: call the clinician" in replans(robot)
    assert (
        robot.pelea_link.graph.edge("test", "clinician", "requests") is None
    )  # cleared at the end


def test_the_person_leaves_speech_stops_and_the_item_starts_again():
    robot = Robot(Patient(leaves={"bladder": 10.0}))
    result = robot.run_test()
    assert result["person_lost_count"] == 1 and result["total"] == 100
    kinds = robot.kinds()
    assert kinds.index("person_lost") < kinds.index("person_back")
    assert "Please, sit down in front of me." in robot.said
    assert [s for s in robot.said if s.startswith("Question 6 of 10")] and len(
        [s for s in robot.said if s.startswith("Question 6 of 10")]
    ) == 2  # asked again
    assert {"clear": True} in robot.screen  # the panel cleared while the person was away
    assert "the person left" in replans(robot)


def test_nobody_there_at_start_asks_to_sit_first():
    robot = Robot(present=False)
    robot.bus.after(
        5.0,
        lambda: robot.person.signal(
            "seen", pose={"translation": [0.9, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]}
        ),
    )
    result = robot.run_test()
    assert robot.said[0] == "Please, sit down in front of me." and robot.said[1].startswith(
        "Hello Carlos"
    )
    assert result["total"] == 100


def test_a_result_cgamed_did_not_answer_is_sent_again_and_stored_once():
    robot = Robot()
    robot.port.store_failures = 2
    result = robot.run_test()
    assert robot.port.stored == [result]
    assert [e["event"] for e in robot.port.events].count("finished") == 1


def test_a_result_cgamed_refused_is_told_to_the_clinician_once_and_not_sent_again():
    robot = Robot()
    robot.port.refuse = "result.items[2]: 'attempts' is a required property"
    robot.hle.start(robot.pelea_link.graph, "Carlos")
    robot.bus.run(until=lambda: not robot.hle.running and robot.port.store_calls > 0, limit=3600)
    with contextlib.suppress(TimedOutError):  # a minute more: nothing is sent again
        robot.bus.run(limit=60)
    assert robot.port.store_calls == 1 and robot.port.stored == []
    [told] = [n for n in robot.port.notifications if "refused" in n]
    assert "'attempts' is a required property" in told and "Carlos" in told
    assert [e["event"] for e in robot.port.events].count("refused") == 1
    assert robot.pelea_link.graph.node("test").attrs.get("status") == "finished"


def test_a_second_start_while_running_is_ignored():
    robot = Robot()
    robot.hle.start(robot.pelea_link.graph, "Carlos")
    assert robot.hle.start(robot.pelea_link.graph, "Someone else") is False
    robot.bus.run(until=lambda: bool(robot.port.stored) and not robot.hle.running)
    assert [r["patient"] for r in robot.port.stored] == ["Carlos"]


def test_the_graph_records_each_answer_and_how_it_was_given():
    robot = Robot(Patient(answers={"stairs": [("touch", 5)]}))
    robot.run_test()
    graph = robot.pelea_link.graph
    assert graph.node("item_stairs").attrs == {
        "item": "stairs",
        "position": 10,
        "attempts": 1,
        "answer": 5,
        "via": "touch",
        "status": "answered",
        "outcomes": ["answered"],
        "heard": "",
        # how it is answered, for the agents that hear and show answers (no copy of the table)
        "answer_kind": "choose",
        "max_points": 10,
        "language": "en",
        "question": "Can you go up and down stairs?",
        "options": ["I cannot use stairs", "I need help on stairs", "I use stairs by myself"],
        "option_points": [0.0, 5.0, 10.0],
        "option_words": [
            "cannot|can't|unable",
            "need help|help me|someone to help",
            "by myself|on my own|independent",
        ],
    }
    assert graph.node("item_feeding").attrs["answer"] == 10


# ------------------------------------------------------------------ crash-only PELEA


def test_how_each_answer_window_ended_is_written_on_its_item():
    robot = Robot(EVERY_PATH)
    robot.run_test()
    graph = robot.pelea_link.graph

    def ended(item):
        attrs = graph.node(f"item_{item}").attrs
        return attrs["outcomes"], attrs["status"], attrs["heard"]

    assert ended("grooming") == (["no_answer", "no_answer"], "unanswered", "")
    assert ended("dressing")[:2] == (["not_understood", "answered"], "answered")
    assert ended("dressing")[2]  # the words that were not understood
    assert ended("bowels") == (["no_answer", "answered"], "answered", "")
    assert ended("bladder") == (["skip"], "unanswered", "skip this one please")


def comparable(result):
    """What a restart must not change (attempts may: the item in progress is asked again)."""
    return (
        {i["item"]: (i["points"], i["via"]) for i in result["items"]},
        result["total"],
        result["unanswered"],
        result["clinician_called"],
        result["patient"],
        result["started"],
    )


def undisturbed():
    return Robot(EVERY_PATH).run_test()


@pytest.mark.parametrize("moment", [0.5, 3, 9, 20, 41, 63, 80, 111, 150, 182, 200, 226, 262, 280])
def test_pelea_killed_at_any_moment_resumes_from_the_dsr(moment):
    expected = undisturbed()
    robot = Robot(EVERY_PATH)
    robot.bus.after(moment, robot.restart_pelea)
    result = robot.run_test()
    assert robot.pelea_restarts == 1
    assert len(robot.port.stored) == 1
    assert comparable(result) == comparable(expected)
    assert result["person_lost_count"] == expected["person_lost_count"]
    if moment < 250:
        assert "resumed" in robot.kinds()


def test_pelea_killed_three_times_still_stores_one_equal_result():
    expected = undisturbed()
    robot = Robot(EVERY_PATH)
    for moment in (25, 90, 170):
        robot.bus.after(moment, robot.restart_pelea)
    result = robot.run_test()
    assert robot.pelea_restarts == 3 and len(robot.port.stored) == 1
    assert comparable(result) == comparable(expected)


def test_a_start_request_in_the_dsr_starts_the_test_and_a_second_is_refused():
    robot = Robot()
    warned = []
    robot.hle.log = type("Log", (), {"warning": warned.append, "info": lambda m: None})()
    # a change from another agent may come before the answer to PELEA's own start_test, while
    # its replica still shows the request PELEA took: not a second Start
    robot.pelea_link.add_listener(lambda d, r: robot.hle.on_graph(robot.pelea_link.graph))
    link = robot.bus.agent("/clarc_cli")
    link.send(request_start("Carlos", "2026-11-24T10:00:00+00:00"))
    robot.bus.run(until=lambda: robot.hle.running, limit=10)
    link.send(request_start("Someone else", "2026-11-24T10:00:05+00:00"))
    robot.bus.run(until=robot.finished)
    assert [r["patient"] for r in robot.port.stored] == ["Carlos"]
    assert [w for w in warned if "refused" in w] == [
        "Start for Someone else while a test runs: refused"
    ]
    assert "requested_patient" not in robot.bus.core.graph.node("test").attrs


@pytest.mark.parametrize("agent", ["speech", "panel"])
@pytest.mark.parametrize("moment", [2, 11, 47, 60, 95, 131, 166, 205, 247])
def test_speech_or_panel_killed_at_any_moment_recover_from_their_grammar(agent, moment):
    expected = undisturbed()
    robot = Robot(EVERY_PATH)
    robot.bus.after(moment, getattr(robot, f"restart_{agent}"))
    result = robot.run_test()
    assert len(robot.port.stored) == 1
    assert comparable(result) == comparable(expected)


def listening_moments(item):
    """When the answer windows of ``item`` open in an undisturbed run (virtual seconds)."""
    robot = Robot(EVERY_PATH)
    robot.run_test()
    return [e["t"] for e in robot.port.events if e["event"] == "listening" and e["item"] == item]


@pytest.mark.parametrize("agent", ["speech", "panel"])
@pytest.mark.parametrize("item", ["feeding", "bathing", "bowels", "stairs"])
def test_an_answer_window_cut_by_a_restart_loses_no_answer(agent, item):
    expected = undisturbed()
    for opened in listening_moments(item):
        robot = Robot(EVERY_PATH)
        inside = []

        def kill(robot=robot, inside=inside):
            inside.append(robot.bus.core.graph.edge("person", "answer", "waiting") is not None)
            getattr(robot, f"restart_{agent}")()

        robot.bus.after(opened + 0.5, kill)
        result = robot.run_test()
        assert inside == [True], "the kill must fall inside the answer window"
        assert comparable(result) == comparable(expected), (agent, item, opened)


def test_bad_taps_and_words_are_refused_and_the_test_goes_on():
    patient = Patient(answers={"feeding": [("touch", 5)]})
    probe = Robot(patient)
    probe.run_test()
    window = next(e["t"] for e in probe.port.events if e["event"] == "listening")
    robot = Robot(patient)
    refused = []
    robot.panel.log = type("Log", (), {"warning": refused.append, "info": refused.append})()
    robot.speech.log = robot.panel.log

    def taps(expect):
        for points in (7, "ten", None, True, 5.5):  # none is an option of feeding (0, 5, 10)
            assert robot.panel.on_tap(robot.panel_runner, robot.panel_link.graph, points) is False
        assert expect in refused[-1]

    robot.bus.after(1.0, lambda: (taps("not an option of the screen"), robot.speech.on_heard("hi")))
    robot.bus.after(window + 0.3, lambda: taps("not an option of feeding"))  # in the window
    result = robot.run_test()
    assert result["total"] == 95 and items(result)["feeding"] == (5, "touch", 1)
    assert len(refused) == 11


def test_a_window_the_dsr_server_restarted_in_is_asked_again_not_counted_as_silence():
    # The answer given during the restart may have been lost to the close: ask again.
    patient = Patient(answers={"feeding": ["silence", ("voice", 5)]})
    probe = Robot(patient)
    probe.run_test()
    opened = next(e["t"] for e in probe.port.events if e["event"] == "listening")
    robot = Robot(Patient(answers={"feeding": ["silence", ("voice", 5)]}))
    robot.bus.after(opened + 0.5, lambda: setattr(robot, "dsr_boot", "boot-2"))
    result = robot.run_test()
    assert items(result)["feeding"] == (5, "voice", 1)  # the window nobody heard is no attempt
    feeding = [
        (e["event"], e.get("window")) for e in robot.port.events if e.get("item") == "feeding"
    ]
    assert ("window_interrupted", 1) in feeding and ("no_answer", 1) not in feeding
    assert result["total"] == probe.port.stored[-1]["total"]


def test_a_close_refused_while_no_answer_came_is_tried_again():
    # The window changed under the close (after a server restart, Speech re-sent can -> waiting
    # and the close named can): refused, with no answer in the graph. Seen in a chaos run.
    robot = Robot(Patient(answers={"feeding": ["silence", ("voice", 5)]}))
    send, refused = robot.port.send, []

    def first_close_refused(tx, on_done=None):
        deletes = [o for o in tx.get("ops", []) if o.get("op") == "delete_edge"]
        if not refused and deletes and deletes[0]["to"] == "answer" and len(tx["ops"]) == 1:
            refused.append(tx)
            tx = dict(tx, preconditions=[{"check": "node_exists", "node": "no_such_node"}])
        send(tx, on_done)

    robot.port.send = first_close_refused
    result = robot.run_test(limit=600)
    assert refused and items(result)["feeding"] == (5, "voice", 2)


HOST_B = ["/speech", "/panel", "/person"]


def cut_for(robot, moment, seconds):
    robot.bus.after(moment, lambda: robot.bus.cut(HOST_B))
    robot.bus.after(moment + seconds, lambda: robot.bus.mend(HOST_B))


@pytest.mark.parametrize("window", range(12))
@pytest.mark.parametrize("offset, seconds", [(0.5, 9.0), (0.5, 30.0), (7.0, 5.0)])
def test_a_cut_across_an_answer_window_loses_no_answer_and_counts_none_twice(
    window, offset, seconds
):
    # The link to Speech, Panel and Person's host goes down while a window is open: what the
    # patient says is heard on that side and held by the link. The window stays open while they
    # are out of reach, and the answer counts once when it arrives; a silence stays a silence.
    probe = Robot(EVERY_PATH)
    expected = probe.run_test()
    opened = [e["t"] for e in probe.port.events if e["event"] == "listening"][window]
    robot = Robot(EVERY_PATH)
    cut_for(robot, opened + offset, seconds)
    result = robot.run_test()
    assert len(robot.port.stored) == 1
    assert comparable(result) == comparable(expected), (window, offset, seconds)
    answers = [e for e in robot.port.events if e["event"] == "answer"]
    assert len(answers) == len({e["item"] for e in answers})  # none counted twice
    assert robot.bus.reach_losses == 1 and not robot.bus.unreachable


@pytest.mark.parametrize("moment", [5, 23, 77, 101, 141, 199, 241])
def test_a_five_second_cut_at_any_moment_changes_nothing_in_the_result(moment):
    expected = undisturbed()
    robot = Robot(EVERY_PATH)
    cut_for(robot, moment, 5.0)
    result = robot.run_test()
    assert comparable(result) == comparable(expected), moment


def test_claims_of_agents_cut_off_end_and_are_taken_again():
    # Speech holds robot -> speaking while it speaks; cut off, the server ends that claim
    # (unreachable); back, Speech takes it again while it still speaks.
    robot = Robot(EVERY_PATH)
    robot.hle.start(robot.pelea_link.graph, "Carlos")
    robot.bus.run(until=lambda: robot.bus.core.claims.all(), limit=60)
    (claim,) = robot.bus.core.claims.all()
    assert claim.agent == "/speech"
    robot.bus.cut(HOST_B)
    robot.bus.run(until=lambda: not robot.bus.core.claims.all(), limit=5)
    robot.bus.mend(HOST_B)
    robot.bus.deliver()
    assert [(c.agent, c.key) for c in robot.bus.core.claims.all()] == [("/speech", claim.key)]


def test_a_claim_taken_by_another_during_the_cut_preempts_the_cut_off_action():
    robot = Robot(EVERY_PATH)
    robot.hle.start(robot.pelea_link.graph, "Carlos")
    robot.bus.run(until=lambda: robot.bus.core.claims.all(), limit=60)
    (claim,) = robot.bus.core.claims.all()
    robot.bus.cut(HOST_B)
    robot.bus.run(until=lambda: not robot.bus.core.claims.all(), limit=5)
    other = robot.bus.agent("/another")
    other.send({"claim": [{"from": "robot", "to": "speaking"}]})
    robot.bus.deliver()
    robot.bus.mend(HOST_B)
    robot.bus.deliver()
    assert [(c.agent, c.key) for c in robot.bus.core.claims.all()] == [("/another", claim.key)]
    assert [ctx.preempted for ctx in robot.speech_runner.running] == [True]


def gone_for_a_while(robot, seconds):
    """Speech and Panel out of reach (a network cut between the hosts): nothing reaches them and
    nothing they send arrives, until they come back and take over from the DSR."""
    robot.speech_link.close()
    robot.panel_link.close()

    def back():
        robot.restart_speech()
        robot.restart_panel()

    robot.bus.after(seconds, back)


@pytest.mark.parametrize("moment", [5, 23, 77, 101, 125, 141, 177, 199, 241])
def test_speech_and_panel_out_of_reach_for_a_while_lose_no_answer(moment):
    # What PELEA sees of a network cut: no agent takes its sentences or its answer windows. It
    # waits for a sentence no one took, and a window no one took is asked again, not silence.
    expected = undisturbed()
    robot = Robot(EVERY_PATH)
    robot.bus.after(moment, lambda: gone_for_a_while(robot, 50.0))
    result = robot.run_test()
    assert len(robot.port.stored) == 1
    assert comparable(result) == comparable(expected), moment
    # and the patient heard every question: none was skipped because no one could say it
    for n, item in enumerate(ORDER, 1):
        question = f"Question {n} of 10, {BY_KEY[item].title}. {BY_KEY[item].question}"
        assert question in robot.said, (moment, question)


def test_speech_hears_by_the_options_the_dsr_carries_not_by_a_table_of_its_own():
    # Change the words of feeding's options on its node: the patient's "I eat on my own" now
    # recognises option 1 (0 points), so Speech read them from the DSR.
    robot = Robot()
    words = ["on my own", "cutting|spreading", "zzz"]
    tx = {
        "ops": [{"op": "set_node_attrs", "node": "item_feeding", "attrs": {"option_words": words}}]
    }
    robot.bus.after(0.01, lambda: robot.pelea_link.send(tx))
    result = robot.run_test()
    assert items(result)["feeding"] == (0, "voice", 1)


@pytest.mark.parametrize("test", ["barthel", "mmse"])
def test_the_shipped_policy_lets_each_agent_write_what_it_writes(test):
    """Every write of a test with deviations (words not understood with their clips, silence, a
    skip, a touch) under clarc_bringup's policy: none refused, the same result as with none."""
    from dsr_graph.model.policy import Policy

    policy = Policy.load(str(REPO / "src" / "clarc_bringup" / "policy" / "clarc.yaml"))
    first, second = ("feeding", "bathing") if test == "barthel" else ("recall", "naming")
    patient = Patient(answers={first: ["garbled", "garbled"], second: ["garbled", "skip"]})
    robot = Robot(patient, test=test, policy=policy)
    result = robot.run_test()
    assert robot.port.stored, "no result stored"
    expected = Robot(patient, test=test).run_test()
    assert [(i["item"], i["points"], i.get("audio")) for i in result["items"]] == [
        (i["item"], i["points"], i.get("audio")) for i in expected["items"]
    ]
    assert next(i for i in result["items"] if i["item"] == first)["needs_clinician"]


def describe(robot, link, state, can_do):
    """An agent's info node as the agent runtime writes it (model/agent_info.py)."""
    from dsr_graph.model.agent_info import info_ops

    attrs = {"state": state, "can_do": can_do}
    link.send({"ops": info_ops(link.graph, link.name, attrs)})
    robot.bus.deliver()


def test_no_question_before_the_agents_it_needs_are_ready_and_a_long_wait_is_told():
    """Speech still starting (as after a kill): the robot says nothing, tells the clinician
    after 30 s, and once Speech is ready runs the test as if nothing had happened."""
    robot = Robot()
    describe(robot, robot.panel_link, "ready", ["show", "take taps"])
    describe(robot, robot.speech_link, "starting", ["speak", "hear"])
    robot.hle.start(robot.pelea_link.graph, "Carlos")
    with contextlib.suppress(TimedOutError):
        robot.bus.run(until=lambda: bool(robot.port.notifications), limit=60)
    assert robot.said == [] and robot.screen == []
    assert "nothing is ready to speak, hear" in robot.port.notifications[0]
    waits = [e for e in robot.port.events if e["event"] == "waiting_for_agents"]
    assert waits and waits[0]["missing"] == ["speak", "hear"]
    describe(robot, robot.speech_link, "ready", ["speak", "hear"])
    robot.bus.run(until=robot.finished, limit=3600)
    result = robot.port.stored[-1]
    assert result["total"] == 100 and robot.said[0].startswith("Hello Carlos")


def test_a_graph_without_agent_info_is_taken_as_before():
    robot = Robot()  # no agent describes itself here: nothing to wait for
    assert robot.run_test()["total"] == 100
    assert not [e for e in robot.port.events if e["event"] == "waiting_for_agents"]


def test_a_window_nobody_could_be_heard_in_is_no_attempt():
    # Speech restarted during the first window of an item the patient leaves silent twice: that
    # window is asked again, and the result says two tries, as undisturbed (a loaded run of the
    # suite stored 3 for a window no listener took in time)
    silent = Patient(answers={"grooming": ["silence", "silence"]})
    probe = Robot(silent)
    undisturbed = items(probe.run_test())["grooming"]
    assert undisturbed == (None, None, 2)
    opened = next(
        e["t"] for e in probe.port.events if e["event"] == "listening" and e["item"] == "grooming"
    )
    robot = Robot(Patient(answers={"grooming": ["silence", "silence"]}))
    robot.bus.after(opened + 0.5, robot.restart_speech)
    assert items(robot.run_test())["grooming"] == undisturbed
    node = robot.pelea_link.graph.node("item_grooming").attrs
    assert node["outcomes"][0] == "interrupted" and node["attempts"] == 2
