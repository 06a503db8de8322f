"""A pydsr agent as CORTEX's are written: it joins the running DSR and prints every signal it
hears as a JSON line; when the file named by its first argument appears, it writes its graph
(CORTEX's format) to its second argument and ends."""

import json
import os
import sys
import time

from pydsr import DSRGraph, signals


def out(*fields):
    print(json.dumps(fields) + "\n", end="", flush=True)  # one write: a log line never splits it


g = DSRGraph(0, "listener", 2)
signals.connect(g, signals.UPDATE_NODE, lambda id, type: out("UPDATE_NODE", id, type))
signals.connect(g, signals.UPDATE_NODE_ATTR, lambda id, names: out("UPDATE_NODE_ATTR", id, names))
signals.connect(g, signals.UPDATE_EDGE, lambda fr, to, type: out("UPDATE_EDGE", fr, to, type))
signals.connect(
    g,
    signals.UPDATE_EDGE_ATTR,
    lambda fr, to, type, names: out("UPDATE_EDGE_ATTR", fr, to, type, names),
)
signals.connect(g, signals.DELETE_EDGE, lambda fr, to, type: out("DELETE_EDGE", fr, to, type))
signals.connect(g, signals.DELETE_NODE, lambda id: out("DELETE_NODE", id))
signals.connect(g, signals.DELETE_NODE_OBJ, lambda node: out("DELETE_NODE_OBJ", node.name))
# the agents' own info nodes it already has: their later state changes are not the writer's
out("READY", g.get_id_from_name("room"), sorted(n.id for n in g.get_nodes_by_type("agent")))
while not os.path.exists(sys.argv[1]):
    time.sleep(0.05)
g.write_to_json_file(sys.argv[2])
g.close()
