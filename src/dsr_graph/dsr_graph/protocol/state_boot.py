"""How the DSR server starts: from the state it stored (its snapshot, then its journal), or, when
it has none, from a world file (or an empty graph), stored at once. Pure: the node gives it the
open store and its parameters and logs the notes it returns.

A stored graph made from another world than the one asked for is refused (``StateMismatch``)
unless ``resume``: a robot must not carry a ward's state into another ward silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from dsr_graph.exceptions import StateMismatch
from dsr_graph.formats.state_store import StateStore, origin_conflict, world_origin
from dsr_graph.formats.world_files import read_world
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import Policy
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol.server_core import ServerCore


@dataclass
class Boot:
    core: ServerCore
    notes: list[tuple[str, str]] = field(default_factory=list)  # (level, message) to log


def boot_state(
    store: StateStore,
    world_file: str,
    vocabulary: Vocabulary,
    policy: Policy,
    limits: dict[str, Any],
    resume: bool = False,
) -> Boot:
    snapshot = store.load_snapshot()
    origin = world_origin(world_file)
    if snapshot is None:
        return _from_world(store, world_file, origin, vocabulary, policy, limits)
    notes = []
    conflict = origin_conflict(store.read_origin(), origin, int(snapshot["seq"]))
    if conflict and not resume:
        raise StateMismatch(
            f"state_dir {store.dir}: {conflict}. Set -p resume:=true to go on with the stored "
            "graph, or give another state_dir (or remove this one) to start from the world"
        )
    if conflict:
        notes.append(
            ("warning", f"state_dir {store.dir}: {conflict}; going on with it (resume:=true)")
        )
    core, replayed, legacy = ServerCore.restore(
        snapshot, store.replay_journal, vocabulary, policy=policy, **limits
    )
    if legacy:
        store.write_snapshot(core.durable_snapshot())
        notes.append(
            (
                "warning",
                f"state_dir {store.dir} was in millimetres (written before units were declared): "
                "converted to metres and stored so",
            )
        )
    notes += [("warning", warning) for warning in store.warnings]
    ignored = f"; world_file {world_file} not loaded (state exists)" if world_file else ""
    notes.append(
        (
            "info",
            f"restored {store.dir}: seq {core.seq} ({replayed} journaled after the snapshot), "
            f"{len(core.graph)} nodes{ignored}",
        )
    )
    return Boot(core, notes)


def _from_world(store, world_file, origin, vocabulary, policy, limits) -> Boot:
    notes = []
    graph = Graph(vocabulary)
    if world_file:
        world = read_world(world_file, vocabulary)
        notes += [("warning", f"world file: left out: {v}") for v in world.violations]
        graph = world.graph
    core = ServerCore(graph, 0, policy=policy, **limits)
    store.write_origin(origin)
    store.write_snapshot(core.durable_snapshot())
    notes.append(
        (
            "info",
            f"new state in {store.dir} from {world_file or 'an empty graph'}: "
            f"{len(graph)} nodes, {graph.edge_count()} edges",
        )
    )
    return Boot(core, notes)
