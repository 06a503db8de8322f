"""The graph's elements: a node (id, name, type, attributes) and an edge (from, to, type,
attributes, an RT edge's rigid transform), each with its version and its attributes'
provenance (when and by whom each was last set)."""

from __future__ import annotations

import sys
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

NodeRef = int | str  # a node id (int) or name (str)
EdgeKey = tuple[int, int, str]  # (from id, to id, type)


class Node:
    # prov: attribute name -> (time, agent) of its last write (model/provenance.py)
    __slots__ = ("id", "name", "type", "attrs", "version", "prov")

    def __init__(
        self,
        id: int,
        name: str,
        type: str,
        attrs: dict[str, Any],
        version: int = 1,
        prov: dict[str, tuple[float, str]] | None = None,
    ):
        self.id = id
        self.name = name
        self.type = type
        self.attrs = attrs
        self.version = version
        self.prov = {} if prov is None else prov

    def __repr__(self) -> str:
        return f"Node({self.id}, {self.name!r}, {self.type!r}, v{self.version})"


class Edge:
    __slots__ = ("src", "dst", "type", "attrs", "version", "rt", "prov")

    def __init__(
        self,
        src: int,
        dst: int,
        type: str,
        attrs: dict[str, Any],
        rt: np.ndarray | None = None,
        version: int = 1,
        prov: dict[str, tuple[float, str]] | None = None,
    ):
        self.src = src
        self.dst = dst
        self.type = type
        self.attrs = attrs
        self.rt = rt
        self.version = version
        self.prov = {} if prov is None else prov

    @property
    def key(self) -> EdgeKey:
        return (self.src, self.dst, self.type)

    def __repr__(self) -> str:
        return f"Edge({self.src}->{self.dst} {self.type!r}, v{self.version})"


def interned_provenance(stamps: Mapping[str, Any]) -> dict[str, tuple[float, str]]:
    """A trusted snapshot element's stamps (lists in JSON) as the graph keeps them."""
    return {name: (t, sys.intern(a)) for name, (t, a) in stamps.items()}


def node_of(decode: Callable[[dict[str, Any]], dict[str, Any]], n: Mapping[str, Any]) -> Node:
    """A trusted snapshot's node (its attributes through ``decode``)."""
    stamps = n.get("provenance")
    return Node(
        n["id"],
        n["name"],
        n["type"],
        decode(n.get("attrs") or {}),
        n.get("version", 1),
        interned_provenance(stamps) if stamps else None,
    )


# the lists of a columnar snapshot's "nodes" and "edges" (formats/dsr_json.py, to_columns)
