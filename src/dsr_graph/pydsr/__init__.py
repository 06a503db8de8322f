"""pydsr: CORTEX's Python API (robocomp/cortex, python-wrapper) on the DSR suite, so that agents
written for CORTEX run here unchanged: ``from pydsr import *``.

    g = DSRGraph(0, "my_agent", 42)          # joins the running dsr_server as /my_agent
    g = DSRGraph(0, "t", 42, "world.json")   # a graph of this process's own, from a world file
    rt = rt_api(g); inner = inner_api(g)
    signals.connect(g, signals.UPDATE_NODE, lambda id, type: ...)

What differs from CORTEX (docs/how-to/from-cortex.md): the transport is ROS 2 and writes go
through the DSR server as transactions (a refused one returns None / False and logs why); the
DSR's rules hold (a node with RT children is not deleted).
"""

from pydsr import signals
from pydsr.camera import camera_api
from pydsr.elements import Attribute, Edge, Node
from pydsr.geometry import inner_api, rt_api
from pydsr.graph import DSRGraph

__all__ = [
    "Attribute",
    "DSRGraph",
    "Edge",
    "Node",
    "camera_api",
    "inner_api",
    "rt_api",
    "signals",
]
