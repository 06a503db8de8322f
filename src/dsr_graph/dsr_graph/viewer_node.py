"""``dsr_viewer`` (also ``dsr view``): a read-only web view of the live DSR, on
http://127.0.0.1:8080/ by default: the graph (nodes by type, labelled symbolic edges, the RT
tree drawn apart), each change highlighted as it happens, a timeline of deltas to scrub back to
any past seq, and an inspector (attributes, version, pose in any other node's frame).

ROS Parameters: host (127.0.0.1), port (8080). Subscriptions and clients: those of DsrAgent.
"""

from __future__ import annotations

import sys
from typing import Any, Dict, List, Optional

import rclpy
from rcl_interfaces.msg import ParameterDescriptor

from . import dsr_format
from .agent import DsrAgent
from .describe import delta_text
from .history import History, SeqUnavailable
from .node_main import run_node
from .viewer_app import make_app
from .web_bridge import Bridge, Broadcaster


class Viewer:
    def __init__(self, node):
        self.node = node
        node.declare_parameter("host", "127.0.0.1", ParameterDescriptor(description="address to serve on", read_only=True))
        node.declare_parameter("port", 8080, ParameterDescriptor(description="port to serve on", read_only=True))
        self.agent = DsrAgent()
        self.history = History()
        self.events = Broadcaster()
        self.bridge = Bridge(node)

    def setup(self, timeout_sec: float = 20.0) -> None:
        self.agent.setup(self.node, timeout_sec=timeout_sec)
        self.agent.add_listener(self._on_change)

    def _on_change(self, deltas: List[Dict[str, Any]], resynced: bool) -> None:
        # ROS thread: hand plain data to the web loop
        snapshot = None
        if resynced:
            snapshot = dsr_format.to_json(self.agent.graph, "snapshot", seq=self.agent.replica.seq)
            deltas = []  # the snapshot already contains them
        self.bridge.to_web(self._apply, snapshot, list(deltas))

    def _apply(self, snapshot: Optional[Dict[str, Any]], deltas: List[Dict[str, Any]]) -> None:
        if snapshot is not None:
            self.history.reset(snapshot)
            self.events.publish("reset", {"seq": self.history.seq})
        for delta in deltas:
            try:
                self.history.add(delta)
            except SeqUnavailable:
                continue  # the replica will resync and send a snapshot
            self.events.publish("delta", dict(delta, text=delta_text(delta)))

    def serve(self) -> bool:
        host = self.node.get_parameter("host").value
        port = self.node.get_parameter("port").value
        return self.bridge.serve(make_app(self.history, self.events), host, port,
                                 on_ready=lambda url: self.node.get_logger().info(f"DSR viewer on {url}"))


def main(args: Optional[List[str]] = None) -> int:
    def body(node) -> int:
        viewer = Viewer(node)
        viewer.setup()
        return 0 if viewer.serve() else 1

    return run_node(lambda: rclpy.create_node("dsr_viewer"), body, args)


if __name__ == "__main__":
    sys.exit(main())
