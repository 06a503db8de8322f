#!/usr/bin/env python3
"""An agent written the CORTEX way (pydsr and its signals, as robocomp's Python agents are):
it follows the CLARC robot's clinical tests and prints, as one JSON line each, every test item
answered, with who wrote the answer and when (an audit a clinician can keep).

    source scripts/env.sh
    scripts/launch.sh &                      # the robot (any scenario)
    python examples/cortex_item_audit.py     # joins the running DSR as /item_audit

It reads only: no policy entry is needed. It ends on Ctrl-C (or SIGTERM).
"""

import json
import signal
import threading
from datetime import UTC, datetime

from pydsr import DSRGraph, signals

AGENT_ID = 77  # unique among CORTEX agents; the DSR knows this one as /item_audit


class ItemAudit:
    def __init__(self, g: DSRGraph):
        self.g = g
        self.seen: dict[str, object] = {}  # item -> the answer last printed
        signals.connect(g, signals.UPDATE_NODE, self.update_node)
        signals.connect(g, signals.UPDATE_NODE_ATTR, self.update_node_att)
        self.say({"event": "joined", "nodes": len(g.get_nodes())})
        for node in g.get_nodes_by_type("test_item"):  # answers given before we joined
            self.report(node)

    @staticmethod
    def say(record: dict) -> None:
        # the line and its end in one write: the ROS logger writes to stderr, which a supervisor
        # may send to the same file, and an unbuffered stdout would write them apart
        print(json.dumps(record) + "\n", end="", flush=True)

    # -- signal handlers, with CORTEX's signatures ---------------------------------------------
    def update_node(self, id: int, type: str) -> None:
        if type == "test_item":  # a test started: its items are made, unanswered
            self.seen.pop(self.g.get_node(id).attrs["item"].value, None)

    def update_node_att(self, id: int, attribute_names: list) -> None:
        node = self.g.get_node(id)
        if node is None:
            return
        if node.type == "test" and "status" in attribute_names:
            status = node.attrs["status"].value
            if status == "running":
                self.say({"event": "test", "test": node.attrs["kind"].value})
        elif node.type == "test_item" and "answer" in attribute_names:
            self.report(node)

    def report(self, node) -> None:
        answer = node.attrs.get("answer")
        if answer is None:
            return
        item = node.attrs["item"].value
        if self.seen.get(item) == answer.value:
            return
        self.seen[item] = answer.value
        when = datetime.fromtimestamp(answer.timestamp / 1e9, UTC)
        via = node.attrs.get("via")
        self.say(
            {
                "event": "answer",
                "item": item,
                "answer": answer.value,
                "via": via.value if via is not None else None,
                "by": answer.agent_name,
                "agent_id": answer.agent_id,
                "at": when.isoformat(timespec="milliseconds"),
            }
        )


def main() -> None:
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    g = DSRGraph(0, "item_audit", AGENT_ID)
    ItemAudit(g)
    stop.wait()
    g.close()


if __name__ == "__main__":
    main()
