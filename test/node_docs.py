"""Whether the topics a running node uses are in its documentation: its module's docstring
(what its reference page shows, docs/reference/generate.py) and, for the DSR's own topics, the
DSR server's page. A topic is documented by its name, by its family with a placeholder for its
last part (``dsr/transactions/<node name>``), or, three parts or more deep, by the family of its
first two (REP-155's ``/humans/persons`` topics: one per person id)."""

from __future__ import annotations

import importlib
from functools import cache
from pathlib import Path

from package_scripts import console_scripts

REPO = Path(__file__).resolve().parents[1]
EVERY_NODE_S = ("/rosout", "/parameter_events")  # rclpy's own, on every node
DSR_PAGE = REPO / "docs" / "reference" / "dsr-server.md"


@cache
def _documentation(node_name: str) -> tuple[str, str]:
    """(the node's module's docstring, the DSR server's page); the executable is the node's
    name."""
    modules = {name: module for (_, name), module in console_scripts().items()}
    module = modules.get(node_name)
    doc = (importlib.import_module(module).__doc__ or "") if module else ""
    return doc, DSR_PAGE.read_text()


def _names(topic: str) -> list[str]:
    parts = topic.strip("/").split("/")
    names = ["/".join(parts)]
    if len(parts) >= 2:
        names.append("/".join(parts[:-1]) + "/<")
    if len(parts) >= 3:
        names.append("/".join(parts[:2]) + " ")
    return names


def undocumented(node_name: str, topics: list[str]) -> list[str]:
    """The ``topics`` of node ``node_name`` that its documentation does not name."""
    doc, dsr = _documentation(node_name)
    missing = []
    for topic in sorted(set(topics) - set(EVERY_NODE_S)):
        texts = [doc, dsr] if topic.startswith("/dsr/") else [doc]
        if not any(name in text for name in _names(topic) for text in texts):
            missing.append(topic)
    return missing


# every rclpy node's own services: its parameters, its types
NODE_SERVICES = frozenset(
    "describe_parameters get_parameter_types get_parameters list_parameters set_parameters"
    " set_parameters_atomically get_type_description".split()
)


def own_services(node_name: str, services: list[str]) -> list[str]:
    """``services`` less the ones every rclpy node serves for itself (``/<node>/<service>``)."""
    return [
        s
        for s in services
        if not (s.startswith(f"/{node_name}/") and s.split("/")[-1] in NODE_SERVICES)
    ]
