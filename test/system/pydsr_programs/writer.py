"""A pydsr agent that writes: a crate under the room, its colour, an edge and its attribute, a
ball on the crate, then removes the edge and the ball. Prints each step's result as JSON. A
handler of its own writes too (a signal's handler may)."""

import json
import threading

from pydsr import Attribute, DSRGraph, Edge, Node, rt_api, signals


def out(*fields):
    print(json.dumps(fields) + "\n", end="", flush=True)  # one write: a log line never splits it


g = DSRGraph(0, "writer", 1)
rt = rt_api(g)
painted = threading.Event()


def paint_balls(id, type):
    """A handler that writes: every ball is painted green (on the signals' thread)."""
    if type == "ball":
        ball = g.get_node(id)
        ball.attrs["color"] = Attribute("green")
        out("painted", g.update_node(ball))
        painted.set()


signals.connect(g, signals.UPDATE_NODE, paint_balls)
room = g.get_id_from_name("room")
crate = Node(1, "box", "crate")
crate.attrs["color"] = Attribute("white")
crate_id = g.insert_node(crate)
out("insert_node", crate_id)
out(
    "rt", rt.insert_or_assign_edge_RT(g.get_node(room), crate_id, [1500.0, 500.0, 0.0], [0, 0, 0.5])
)
node = g.get_node(crate_id)
node.attrs["color"].value = "red"
out("update_node", g.update_node(node))
out("edge", g.insert_or_assign_edge(Edge(room, crate_id, "in", 1)))
edge = g.get_edge(crate_id, room, "in")
edge.attrs["color"] = Attribute("blue")
out("edge_attr", g.insert_or_assign_edge(edge))
ball_id = g.insert_node(Node(1, "ball", "ball"))
out("ball", ball_id)
out("painted_in_time", painted.wait(30))
out("ball_rt", rt.insert_or_assign_edge_RT(g.get_node(crate_id), ball_id, [0, 0, 300.0], [0, 0, 0]))
out("delete_edge", g.delete_edge(crate_id, room, "in"))
out("delete_node", g.delete_node(ball_id))
out("refused", g.delete_node(room))  # it has RT children: the DSR keeps every pose
# no g.close(): CORTEX's programs end without one, and must end cleanly (exit 0)
