"""What the screen takes just before its answer window opens (the patient did not wait for the
robot to finish asking, or the window's opening was slow on a busy machine) is kept a moment
and answers the window of the item on the screen: a tap, a drawing, or the shapes touched."""

from clarc_agents import definitions
from clarc_agents.behaviours.panel import PanelBehaviour
from clarc_agents.questionnaire.item_options import answer_attrs, item_node
from dsr_graph.model.graph import Graph


class Runner:
    def __init__(self):
        self.signals = []

    def signal(self, name, **values):
        self.signals.append((name, values))
        return True


class Log:
    def __init__(self):
        self.lines = []

    def warning(self, line, **_):
        self.lines.append(line)

    info = warning


def screen_showing(key: str) -> Graph:
    item = definitions.load("mmse").item(key)
    graph = Graph()
    for name, kind in (("test", "test"), ("test_part", "test_part"), ("person", "person")):
        graph.insert_node(name, kind)
    graph.insert_node("answer", "state")
    graph.insert_node(item_node(key), "test_item", attrs=answer_attrs(item))
    shows = [s.lower() for s in item.shows]
    graph.insert_edge("test", "test_part", "is_in", attrs={"item": key, "shows": shows})
    return graph


def open_window(graph: Graph, key: str) -> None:
    graph.insert_edge("person", "answer", "waiting", attrs={"item": key})


def test_a_drawing_made_before_the_window_answers_it_when_it_opens():
    graph, runner, log = screen_showing("copying"), Runner(), Log()
    panel = PanelBehaviour(screen=None, log=log)
    assert not panel.on_drawing(runner, graph, "M 1 2 L 3 4")
    assert "kept unless a window for copying opens" in log.lines[-1]
    open_window(graph, "copying")
    panel.on_graph(runner, graph)
    assert runner.signals == [("drawn", {"drawing": "M 1 2 L 3 4"})]


def test_shapes_touched_before_the_window_are_scored_in_it():
    graph, runner, log = screen_showing("command"), Runner(), Log()
    panel = PanelBehaviour(screen=None, log=log)
    for shape in ("circle", "square"):
        assert not panel.on_target(runner, graph, shape)
    open_window(graph, "command")
    panel.on_graph(runner, graph)
    assert panel.on_target(runner, graph, "triangle")
    assert runner.signals[-1] == ("touched", {"points": 3, "heard": "circle, square, triangle"})


def test_what_was_kept_for_another_item_is_dropped():
    graph, runner, log = screen_showing("copying"), Runner(), Log()
    panel = PanelBehaviour(screen=None, log=log)
    panel.on_drawing(runner, graph, "M 1 2 L 3 4")
    open_window(graph, "writing")
    panel.on_graph(runner, graph)
    assert runner.signals == []
