"""pydsr's values: ``Attribute``, ``Node`` and ``Edge`` as CORTEX's Python API has them
(robocomp/cortex, python-wrapper/python_api.cpp): detached copies a program reads and edits, then
hands to ``DSRGraph.update_node`` / ``insert_or_assign_edge``. Pure: no graph, no ROS.

CORTEX's conventions are kept here: a node type outside CORTEX's registry raises RuntimeError, an
attribute keeps the kind of value it was made with (TypeError otherwise), ``timestamp`` (ns) and
``agent_id`` change with the value, an edge is ``Edge(to, from, type, agent_id)``.
"""

from __future__ import annotations

import time
import zlib
from typing import Any

from pydsr import value_types

# CORTEX's node type registry (core/include/dsr/core/types/type_checking/dsr_node_type.h), with
# "root", the type of a CORTEX world's root in its own files and tests
CORTEX_NODE_TYPES = frozenset(
    """root world transform room differentialrobot omnirobot robot path_to_target intention rgbd
    pan_tilt battery pose laser ultrasound camera imu slam_device object affordance_space person
    personal_space plane box cylinder ball mesh face nape body head trunk hip chest nose left_eye
    right_eye left_ear right_ear left_arm right_arm left_shoulder right_shoulder left_elbow
    right_elbow left_wrist right_wrist left_hand right_hand left_hip right_hip left_leg right_leg
    left_knee right_knee mug cup noodles table chair shelve dish spoon testtype glass plant
    microwave oven vase refrigerator book bottle fork knife bowl diningtable container road
    building vehicle gps grid task compressed agent wayp servo virtual_person""".split()
)

# the id of the agent that made the last DSRGraph: CORTEX stamps new values with it
_local_agent = {"id": 0}


def set_local_agent_id(agent_id: int) -> None:
    _local_agent["id"] = int(agent_id)


def now_ns() -> int:
    return time.time_ns()


def agent_number(name: str) -> int:
    """CORTEX's integer agent id for a DSR agent, known by its node name: its CRC-32, the same
    in every process (the DSR stamps names; CORTEX's ids are programs' own numbers)."""
    return zlib.crc32(name.encode("utf-8"))


class Attribute:
    """``Attribute(value, timestamp, agent_id)``, ``Attribute(value, agent_id)`` or
    ``Attribute(value)`` (stamped now, by the local agent)."""

    __slots__ = ("_kind", "_value", "_timestamp", "_agent_id", "_agent_name", "_declared")

    def __init__(self, value: Any, *args: int, **kwargs: int):
        if len(args) > 2:
            raise TypeError("Attribute(value, timestamp, agent_id) takes at most 3 arguments")
        names = ("timestamp", "agent_id") if len(args) + len(kwargs) == 2 else ("agent_id",)
        given = dict(zip(names, args, strict=False))
        for key, v in kwargs.items():
            if key not in ("timestamp", "agent_id") or key in given:
                raise TypeError(f"Attribute() got an unexpected argument {key!r}")
            given[key] = v
        self._kind = value_types.kind_of(value)
        self._declared: tuple[str, int | None] | None = None  # its name's type, once in a map
        self._value = value_types.stored(value, self._kind, None)
        self._timestamp = int(given.get("timestamp", now_ns()))
        self._agent_id = int(given.get("agent_id", _local_agent["id"]))
        self._agent_name = ""

    def _bind(self, name: str) -> None:
        """It is now the attribute called ``name``: its value must fit that name's type."""
        declared = value_types.declared_type(name)
        if declared is not None:
            if not value_types.accepts(declared, self._kind, self._value):
                raise TypeError(
                    f"attribute {name!r} is {value_types.describe(declared)}: a {self._kind} "
                    "value does not fit it"
                )
            self._value = value_types.stored(self._value, self._kind, declared)
        self._declared = declared

    @property
    def value(self) -> Any:
        return self._value

    @value.setter
    def value(self, value: Any) -> None:
        kind = value_types.kind_of(value)
        if self._declared is not None:
            fits = value_types.accepts(self._declared, kind, value)
            selected = value_types.describe(self._declared)
        else:
            fits = value_types.same_family(kind, self._kind)
            selected = self._kind
        if not fits:
            raise TypeError(
                f"Attributes cannot change type. Selected type is {selected} and used type is "
                f"{kind}"
            )
        self._kind = kind
        self._value = value_types.stored(value, kind, self._declared)
        self._timestamp = now_ns()
        self._agent_id = _local_agent["id"]
        self._agent_name = ""

    @property
    def timestamp(self) -> int:
        """When the value was written, in ns since the epoch (read-only)."""
        return self._timestamp

    @property
    def agent_id(self) -> int:
        """The id of the agent that wrote the value (read-only). Read from the graph: the
        number of the writer's node name (``agent_number``)."""
        return self._agent_id

    @property
    def agent_name(self) -> str:
        """The writer's ROS node name, for a value read from the graph ("" otherwise; not
        CORTEX's)."""
        return self._agent_name

    def __repr__(self) -> str:
        return f" < {self._value!r} > "


class AttributeMap(dict):
    """A node's or an edge's attributes: name -> ``Attribute``, each checked against its name's
    type as it goes in (CORTEX's typed map)."""

    def __setitem__(self, name: str, attribute: Attribute) -> None:
        if not isinstance(name, str) or not isinstance(attribute, Attribute):
            raise TypeError("attrs maps a name (str) to an Attribute")
        attribute._bind(name)
        super().__setitem__(name, attribute)

    def update(self, *args: Any, **kwargs: Any) -> None:
        for name, attribute in dict(*args, **kwargs).items():
            self[name] = attribute

    def setdefault(self, name: str, default: Any = None) -> Any:
        if name not in self:
            self[name] = default
        return self[name]


class Edge:
    """``Edge(to, from, type, agent_id)``: CORTEX's argument order, destination first."""

    __slots__ = ("_to", "_from", "_type", "agent_id", "attrs")

    def __init__(
        self, to: int, frm: int | None = None, type: str = "", agent_id: int = 0, **kwargs: Any
    ):
        # CORTEX's keyword for the origin is ``from``: Edge(to=2, **{"from": 1}, type="in", ...)
        if kwargs.keys() - {"from"}:
            raise TypeError(f"Edge() got unexpected arguments {sorted(kwargs.keys() - {'from'})}")
        if (frm is None) == ("from" not in kwargs):
            raise TypeError("Edge(to, from, type, agent_id) needs its origin, once")
        if not type:
            raise TypeError("Edge(to, from, type, agent_id) needs its type")
        self._to = int(to)
        self._from = int(kwargs["from"] if frm is None else frm)
        self._type = str(type)
        self.agent_id = int(agent_id)
        self.attrs: AttributeMap = AttributeMap()

    @property
    def type(self) -> str:
        return self._type

    @property
    def origin(self) -> int:
        return self._from

    @property
    def destination(self) -> int:
        return self._to

    def __repr__(self) -> str:
        lines = [f"Type: {self._type} from: {self._from} to: {self._to}"]
        lines += [f"      [{k}] -- {v!r}" for k, v in self.attrs.items()]
        return "\n".join(lines)


class Node:
    """``Node(agent_id, type, name="")``; ``id`` is given when the graph inserts it. ``edges``
    maps ``(to, type)`` to the node's outgoing edges."""

    __slots__ = ("_id", "_type", "_name", "agent_id", "attrs", "edges")

    def __init__(self, agent_id: int, type: str, name: str = ""):
        if type not in CORTEX_NODE_TYPES:
            raise RuntimeError(f"Error, {type} is not a valid node type")
        self._id = 0
        self._type = type
        self._name = name
        self.agent_id = int(agent_id)
        self.attrs: AttributeMap = AttributeMap()
        self.edges: dict[tuple[int, str], Edge] = {}

    @classmethod
    def _of(cls, id: int, type: str, name: str, agent_id: int = 0) -> Node:
        """A node as the graph holds it, whatever its type (the suite's own types included)."""
        node = cls.__new__(cls)
        node._id, node._type, node._name, node.agent_id = id, type, name, agent_id
        node.attrs, node.edges = AttributeMap(), {}
        return node

    @property
    def id(self) -> int:
        return self._id

    @property
    def name(self) -> str:
        return self._name

    @property
    def type(self) -> str:
        return self._type

    def get_edges(self) -> list[Edge]:
        return list(self.edges.values())

    def __repr__(self) -> str:
        lines = [
            f"Node: {self._id}",
            f"  Type: {self._type}",
            f"  Name: {self._name}",
            f"  Agent id: {self.agent_id}",
            "  ATTRIBUTES: [",
        ]
        lines += [f"      [{k}] -- {v!r}" for k, v in self.attrs.items()]
        lines += ["   ]", "  EDGES: ["]
        lines += [
            f"          Edge type: {e.type} from: {e.origin} to: {e.destination}"
            for e in self.edges.values()
        ]
        lines += ["          ]"]
        return "\n".join(lines)
