"""``dsr_viewer`` (also ``dsr view``): a read-only web view of the live DSR, on
http://127.0.0.1:8080/ by default: the graph (nodes by type, labelled symbolic edges, the RT
tree drawn apart), each change highlighted as it happens, a timeline of deltas to scrub back to
any past seq, and an inspector (attributes, version, pose in any other node's frame).

ROS Parameters: host (127.0.0.1), port (8080), setup_timeout (20 s), token (the access token
every request needs; empty: a new one at each start, printed in the address it logs),
allowed_hosts (Host names served besides the loopback ones, comma-separated).
Subscriptions and clients: those of DsrAgent, and dsr/get_blob and every agent's
dsr/get_blob/<node name> (a camera image whose bytes went by before the viewer listened to their
topic: sensor data's are with the agent that wrote it).
"""

from __future__ import annotations

from typing import Any

from dsr_graph.exceptions import SeqUnavailable
from dsr_graph.formats import dsr_json
from dsr_graph.protocol.delta_text import delta_text
from dsr_graph.protocol.history import History
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.blob_service import AsyncBlobClient
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.parameters import (
    allowed_hosts_of,
    declare,
    declare_allowed_hosts,
    declare_setup_timeout,
    float_param,
    param,
)
from dsr_graph.ros.web_bridge import Bridge
from dsr_graph.web.events import Broadcaster
from dsr_graph.web.guard import new_token
from dsr_graph.web.viewer_app import make_app

BLOB_WAIT = 5.0  # seconds for the answer of dsr/get_blob (the server's or a writer's)
BLOB_DISCOVERY = 1.0  # seconds between looks for agents' dsr/get_blob/<node name>


class Viewer(DsrNode):
    NAME = "dsr_viewer"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "host", "127.0.0.1", "address to serve on", read_only=True)
        declare(
            node,
            "port",
            8080,
            "port to serve on (0: any free port)",
            read_only=True,
            minimum=0,
            maximum=65535,
        )
        declare_setup_timeout(node, 20.0)
        declare(
            node,
            "token",
            "",
            "access token of the page (empty: a new one, printed at start)",
            read_only=True,
        )
        declare_allowed_hosts(node)

    def __init__(self) -> None:
        super().__init__()
        # the inspector shows a camera's latest image; it reads, never writes
        self.agent = DsrAgent(blobs=True, describe=False)
        self.history = History()
        self.events = Broadcaster()
        self.bridge: Bridge | None = None
        self.blobs: AsyncBlobClient | None = None

    def setup(self) -> None:
        self.agent.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        self.agent.add_listener(self._on_change)
        self.blobs = AsyncBlobClient(self, timeout=BLOB_WAIT)
        # the writers of sensor data, whose bytes only they hold: looked for on the ROS thread
        self.create_timer(BLOB_DISCOVERY, self.blobs.discover)
        self.bridge = Bridge(self)

    def _on_change(self, deltas: list[dict[str, Any]], resynced: bool) -> None:
        # ROS thread: hand plain data to the web loop
        snapshot = None
        if resynced:
            snapshot = dsr_json.to_json(self.agent.graph, "snapshot", seq=self.agent.replica.seq)
            deltas = []  # the snapshot already contains them
        self.bridge.to_web(self._apply, snapshot, list(deltas))

    def _apply(self, snapshot: dict[str, Any] | None, deltas: list[dict[str, Any]]) -> None:
        if snapshot is not None:
            self.history.reset(snapshot)
            self.events.publish("reset", {"seq": self.history.seq})
        for delta in deltas:
            try:
                self.history.add(delta)
            except SeqUnavailable:
                continue  # the replica will resync and send a snapshot
            if self.events.listening:  # its text is for the pages open now (the timeline's
                # past deltas are texted when a page asks for them)
                self.events.publish("delta", dict(delta, text=delta_text(delta)))

    def run(self) -> int:
        token = param(self, "token") or new_token()
        hosts = allowed_hosts_of(self)
        served = self.bridge.serve(
            make_app(
                self.history, self.events, token=token, hosts=hosts, fetch_blob=self.blobs.fetch
            ),
            param(self, "host"),
            param(self, "port"),
            on_ready=lambda url: self.get_logger().info(f"DSR viewer on {url}?token={token}"),
        )
        return 0 if served else 1


main = main_for(Viewer)
