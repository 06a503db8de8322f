"""A sentence the speaker cuts on its own (not at Speech's request) ends as said: the robot's
speaking channel is freed and the test goes on (a loaded run's stalled Barthel, issue 36)."""

from local_clarc import Patient, Robot


class CuttingSpeaker(Robot):
    """The speaker reports the first "Let me say the options again" as stopped, as a speaker
    may when something else cuts it."""

    cut = False

    def say(self, sid, text):
        if not self.cut and text.startswith("Let me say the options again"):
            self.cut = True
            self.said.append(text)
            self.bus.soon(lambda: self.speech.on_speaker(sid, "start"))
            self.bus.after(1.0, lambda: self.speech.on_speaker(sid, "stopped"))
            return
        super().say(sid, text)


def test_a_sentence_the_speaker_cuts_on_its_own_is_taken_as_said():
    robot = CuttingSpeaker(Patient(answers={"bowels": ["silence", ("voice", 10)]}))
    result = robot.run_test("Carlos", limit=600.0)
    assert robot.cut
    bowels = next(i for i in result["items"] if i["item"] == "bowels")
    assert (bowels["points"], bowels["via"], bowels["attempts"]) == (10, "voice", 2)
    assert len(result["items"]) == 10 and result["items"][-1]["points"] is not None


def test_a_sentence_speech_stops_is_still_interrupted():
    """The person leaving stops the sentence (the stop rule): that path is unchanged."""
    from local_clarc import EVERY_PATH

    result = Robot(EVERY_PATH).run_test()
    assert result["person_lost"] >= 1 and len(result["items"]) == 10


class StuckSpeaker(Robot):
    """The speaker starts the greeting and reports its end only ``stuck_for`` seconds later (a
    speaker, or a Speech, that never frees the robot's speaking channel)."""

    stuck_for = 200.0

    def say(self, sid, text):
        if text.startswith("Hello"):
            self.said.append(text)
            self.bus.soon(lambda: self.speech.on_speaker(sid, "start"))
            self.bus.after(self.stuck_for, lambda: self.speech.on_speaker(sid, "end"))
            return
        super().say(sid, text)


def test_a_channel_never_freed_is_told_to_the_clinician_and_the_test_goes_on_once_free():
    robot = StuckSpeaker()
    result = robot.run_test("Carlos", limit=3600.0)
    busy = [e for e in robot.port.events if e["event"] == "channels_busy"]
    assert [e["busy"] for e in busy] == [["speaking"]]
    told = [n for n in robot.port.notifications if "has not ended its speaking" in n]
    assert len(told) == 1
    assert result["total"] == 100 and len(result["items"]) == 10
