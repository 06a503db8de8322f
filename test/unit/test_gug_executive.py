"""PELEA running a whole Get Up & Go test through the DSR (no ROS, virtual time): it explains,
says go, waits for the gait analyser's timed result and stores it; a patient who walks out of
view has the trial repeated; one who never rises is given up on and the clinician called; a
PELEA restarted mid-trial goes on from the DSR (test/local_gug.py)."""

import pytest
from gug_checks import check_timed
from local_gug import GugRobot
from pyperplan.pddl.parser import Parser

from clarc_agents.gug import sentences
from clarc_agents.gug.phases import RISE_WITHIN, WITHIN
from clarc_agents.pelea import decision_support
from clarc_agents.pelea.gug_executive import MAX_TRIALS, VERDICT_WAIT, GugExecutive
from clarc_sim.patient.gait_motion import Motion

MOTION = Motion(reaction=1.0, rise=2.0, walk_out=4.0, turn=2.0, walk_back=4.0, sit=3.0)


def within_tolerance(result, motion=MOTION):
    check_timed(result, motion)


def test_every_action_of_the_domain_has_a_handler():
    parser = Parser(decision_support.domain_path("gug"))
    domain = parser.parse_domain()
    assert set(GugExecutive.ACTIONS) == set(domain.actions)


def test_a_whole_test_is_run_timed_and_stored():
    robot = GugRobot(MOTION, noise_mm=10, drop_rate=0.1)
    result = robot.run_gug()
    assert result["test"] == "get_up_and_go" and result["patient"] == "Carlos"
    within_tolerance(result)
    assert result["trials"] == 1 and not result["person_lost"]
    assert result["band"] == "mostly independent" and result["fall_risk"] is True  # 16 s
    told = (sentences.EXPLAIN, sentences.SIT, sentences.GO, sentences.DONE)
    assert [s for s in robot.said if s in told] == list(told)  # explained, seated, go, goodbye
    phases = [e["phase"] for e in robot.port.events if e["event"] == "phase"]
    assert phases[-1] in ("sit", "done") and "walk_out" in phases
    assert robot.bus.core.graph.node("test").attrs["kind"] == "get_up_and_go"


def test_a_patient_who_walks_away_mid_trial_is_asked_to_sit_and_the_trial_repeated():
    robot = GugRobot(MOTION, leave=6.0)
    result = robot.run_gug()
    within_tolerance(result)
    assert result["trials"] == 2 and result["person_lost"] and result["person_lost_count"] == 1
    assert robot.said.count(sentences.SIT) == 3 and sentences.AGAIN in robot.said
    assert robot.said.count(sentences.GO) == 2
    assert ("trial_void", 1) in [(e["event"], e.get("trial")) for e in robot.port.events]


def test_a_patient_who_never_rises_is_stored_unable_to_perform_and_the_clinician_called():
    robot = GugRobot(MOTION, rises=False, seen_for=RISE_WITHIN + 5.0, hz=5.0)
    result = robot.run_gug()
    assert result["outcome"] == "unable" and result["band"] == "unable to perform"
    assert result["tug_seconds"] is None and result["phases"] is None
    assert result["trials"] == MAX_TRIALS and result["fall_risk"] is True
    assert result["void_reasons"] == [
        f"trial {n}: did not rise within 30 s of go" for n in range(1, MAX_TRIALS + 1)
    ]
    assert result["clinician_called"] is True
    assert robot.said.count(sentences.GO) == MAX_TRIALS
    assert robot.port.notifications and "could not be timed" in robot.port.notifications[0]
    test = robot.bus.core.graph.node("test").attrs
    assert test["status"] == "finished" and test["clinician_called"] is True


def test_frames_that_come_late_are_judged_on_their_stamps_and_the_trial_is_timed():
    # a busy machine: the end of the trial reaches the DSR long after the 90 s limit
    robot = GugRobot(MOTION, lag_per_second=9.0)
    result = robot.run_gug()
    within_tolerance(result)
    assert result["trials"] == 1 and not result["void_reasons"]
    timed = next(e["t"] for e in robot.port.events if e["event"] == "timed")
    go = next(e["t"] for e in robot.port.events if e["event"] == "trial")
    assert timed - go > WITHIN + VERDICT_WAIT  # PELEA waited on while frames still came


def test_no_gait_analyser_voids_each_trial_once_its_frames_pass_the_limit():
    robot = GugRobot(MOTION, analyser=False, seen_for=WITHIN + 2 * VERDICT_WAIT + 5.0, hz=2.0)
    result = robot.run_gug()
    assert result["outcome"] == "unable" and result["trials"] == MAX_TRIALS
    assert result["void_reasons"] == [
        f"trial {n}: the gait analyser gave no verdict on frames past its 90 s limit"
        for n in range(1, MAX_TRIALS + 1)
    ]


def test_no_frames_after_go_voids_the_trial_naming_the_silence():
    robot = GugRobot(MOTION, seen_for=0.0, hz=1.0)  # the Kinect stops at go
    result = robot.run_gug()
    assert result["outcome"] == "unable"
    assert result["void_reasons"] == [
        f"trial {n}: no frames of the patient after 0.0 s from go" for n in range(1, MAX_TRIALS + 1)
    ]


@pytest.mark.parametrize("moment", [2.0, 12.0, 20.0, 30.0])
def test_pelea_restarted_during_the_test_goes_on_from_the_dsr(moment):
    robot = GugRobot(MOTION)
    robot.bus.after(moment, robot.restart_pelea)
    result = robot.run_gug()
    within_tolerance(result)
    assert len(robot.port.stored) == 1 and robot.pelea_restarts == 1


def test_observers_read_the_whole_test_from_the_dsr():
    # what the launch's monitor and the clinician's dashboard print (clarc_agents/course.py)
    from datetime import UTC, datetime

    from clarc_agents.course import Course

    robot = GugRobot(MOTION, leave=6.0)
    since = datetime.fromtimestamp(robot.port.epoch(), UTC)  # the observer's own test
    link, course, events = robot.bus.agent("/observer"), Course(since), []
    link.add_listener(lambda d, r: events.extend(course.follow(link.graph)))
    result = robot.run_gug()
    kinds = [(e["event"], e.get("trial")) for e in events if e["event"] != "phase"]
    assert kinds == [
        ("started", None),
        ("trial", 1),
        ("person_lost", None),
        ("trial_void", 1),
        ("person_back", None),
        ("trial", 2),
        ("timed", 2),
        ("finished", None),
    ]
    assert events[0]["test"] == "get_up_and_go" and events[-1]["result"] == result
    phases = [e["phase"] for e in events if e["event"] == "phase" and e["trial"] == 2]
    assert phases == ["rise", "walk_out", "turn", "walk_back", "sit"]


@pytest.mark.parametrize("noise_mm", [0, 25])
def test_the_person_s_posture_follows_the_skeleton_as_a_rule_writes_it(noise_mm):
    robot = GugRobot(MOTION, noise_mm=noise_mm)
    robot.run_gug()
    # up, out, the turn on the spot, back, and down again
    assert robot.postures == [
        "sitting",
        "standing",
        "walking",
        "standing",
        "walking",
        "standing",
        "sitting",
    ]


def test_a_gait_analyser_restarted_mid_trial_voids_it_and_the_trial_is_repeated():
    robot = GugRobot(MOTION)
    robot.bus.after(24.0, robot.restart_analyser)  # a few seconds into the first trial
    result = robot.run_gug()
    within_tolerance(result)
    assert result["trials"] == 2 and robot.said.count(sentences.GO) == 2
