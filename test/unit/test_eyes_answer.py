"""The MMSE's reading item is answered by the camera: eyes closed a second of the patient's time
while its window is open, or just before it opened (the patient read the screen and did not wait
for the robot to finish asking, or the window's opening was slow on a busy machine)."""

from clarc_agents import definitions
from clarc_agents.behaviours.closed_eyes import EyesAnswer
from clarc_agents.questionnaire.item_options import answer_attrs, item_node
from dsr_graph.model.graph import Graph

SCALE = 0.1  # a tenth of the patient's time: 0.1 s is a second


class Clock:
    def __init__(self):
        self.t = 100.0

    def __call__(self):
        return self.t


def screen_showing(key: str) -> Graph:
    graph = Graph()
    for name, kind in (("test", "test"), ("test_part", "test_part"), ("person", "person")):
        graph.insert_node(name, kind)
    graph.insert_node("answer", "state")
    for item in definitions.load("mmse").items:
        graph.insert_node(item_node(item.key), "test_item", attrs=answer_attrs(item))
    graph.insert_edge("test", "test_part", "is_in", attrs={"item": key})
    return graph


def close_for(eyes: EyesAnswer, graph: Graph, seconds: float, start: float = 10.0) -> list:
    """Frames at 30 a second of wall time with the eyes closed for ``seconds`` of the patient's
    time, then one open frame: what each answered."""
    frames = int(seconds * SCALE * 30)
    said = [eyes.see(graph, True, start + k / 30) for k in range(frames + 1)]
    return [*said, eyes.see(graph, False, start + (frames + 1) / 30)]


def test_eyes_closed_in_the_window_answer_it():
    graph, eyes = screen_showing("reading"), EyesAnswer(SCALE, Clock())
    graph.insert_edge("person", "answer", "waiting", attrs={"item": "reading"})
    said = close_for(eyes, graph, 3.0)
    assert 1 in said and set(said) <= {None, 1}


def test_eyes_closed_before_the_window_opened_answer_it_when_it_opens():
    clock = Clock()
    graph, eyes = screen_showing("reading"), EyesAnswer(SCALE, clock)
    assert set(close_for(eyes, graph, 3.0)) == {None}  # no window yet: nothing to answer
    clock.t += 0.5
    graph.insert_edge("person", "answer", "waiting", attrs={"item": "reading"})
    assert eyes.on_graph(graph) == 1
    assert eyes.on_graph(graph) is None  # taken once


def test_a_closing_kept_too_long_or_for_another_item_answers_nothing():
    clock = Clock()
    graph, eyes = screen_showing("reading"), EyesAnswer(SCALE, clock)
    close_for(eyes, graph, 3.0)
    clock.t += 10.0  # the window opened long after: the patient was not answering it
    graph.insert_edge("person", "answer", "waiting", attrs={"item": "reading"})
    assert eyes.on_graph(graph) is None

    graph = screen_showing("writing")  # eyes closed while another item is on the screen
    eyes = EyesAnswer(SCALE, clock)
    close_for(eyes, graph, 3.0)
    graph.insert_edge("person", "answer", "waiting", attrs={"item": "writing"})
    assert eyes.on_graph(graph) is None


def test_a_blink_before_the_window_is_never_kept():
    graph, eyes = screen_showing("reading"), EyesAnswer(SCALE, Clock())
    close_for(eyes, graph, 0.4)
    graph.insert_edge("person", "answer", "waiting", attrs={"item": "reading"})
    assert eyes.on_graph(graph) is None
