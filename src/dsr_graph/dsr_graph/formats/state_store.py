"""Durable server state in a directory: a snapshot plus a journal of the deltas after it.

    state_dir/snapshot.json   {"format": "dsr-graph", "kind": "snapshot", "seq": S, ...,
                               "claims": [...]}
    state_dir/journal.jsonl   one accepted delta per line, seq S+1, S+2, ...
    state_dir/lock            held (flock) by the running server: one server per directory
    state_dir/origin.json     what the graph was first made from: {"world_file", "sha256"}
                              (both "" for an empty graph); a server started with another
                              world on this directory refuses unless told to resume

Deltas reach the journal in group commits (formats/group_commit.py): written and fdatasync'ed
after the server broadcast them and before their writers hear they were accepted, so an
acknowledged change survives kill -9 and power loss. Compaction writes a new snapshot
atomically (temp file, fsync, rename, fsync of the directory) and only then empties the
journal; a crash in between replays nothing twice, because journal lines at or below the
snapshot's seq are skipped. A torn last line (a crash in the middle of a write) was never
acknowledged, and is dropped with a warning. What is replayed is synced again at the start:
lines a killed server wrote but did not sync are durable then.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import logging
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from dsr_graph.exceptions import CorruptState, StateDirLocked
from dsr_graph.formats.private_files import private_dir
from dsr_graph.formats.world_files import write_json_atomically
from dsr_graph.model.binary import compact

log = logging.getLogger("dsr_graph.state_store")

SNAPSHOT = "snapshot.json"
JOURNAL = "journal.jsonl"
LOCK = "lock"
ORIGIN = "origin.json"


def world_origin(world_file: str) -> dict[str, str]:
    """What a graph is made from: the world file's absolute path and the SHA-256 of its bytes
    (the content decides: the same world moved elsewhere is the same origin)."""
    if not world_file:
        return {"world_file": "", "sha256": ""}
    path = Path(world_file).resolve()
    return {"world_file": str(path), "sha256": hashlib.sha256(path.read_bytes()).hexdigest()}


def origin_conflict(stored: dict[str, str] | None, wanted: dict[str, str], seq: int) -> str | None:
    """Why a state made from ``stored`` must not be taken for ``wanted`` (None: it may). A state
    without a record (older than origin.json) or started without a world file is taken."""
    if stored is None or not wanted["sha256"] or stored.get("sha256") == wanted["sha256"]:
        return None
    made_from = stored.get("world_file") or "an empty graph"
    return (
        f"it holds a graph made from {made_from} (now at seq {seq}), "
        f"not from world_file {wanted['world_file']}"
    )


class StateStore:
    def __init__(self, directory: os.PathLike, compact_every: int = 1000):
        self.dir = Path(directory)
        self.compact_every = compact_every
        self._journal = None
        self._lock_file = None
        self._since_compaction = 0
        self.warnings: list[str] = []

    # ------------------------------------------------------------------ lifetime
    def open(self) -> None:
        private_dir(self.dir)  # the graph holds patients' names and answers
        self._lock_file = open(self.dir / LOCK, "a+")
        try:
            fcntl.flock(self._lock_file, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self._lock_file.close()
            self._lock_file = None
            raise StateDirLocked(
                f"state directory {self.dir} is in use by another dsr_server"
            ) from None

    def close(self) -> None:
        if self._journal is not None:
            self.flush()
            self._journal.close()
            self._journal = None
        if self._lock_file is not None:
            self._lock_file.close()
            self._lock_file = None

    # ------------------------------------------------------------------ reading
    def _read(self, name: str) -> Any:
        """A JSON file of the state; None if absent, CorruptState if unreadable."""
        path = self.dir / name
        if not path.exists():
            return None
        try:
            return json.loads(path.read_text("utf-8"))
        except (OSError, json.JSONDecodeError) as e:
            raise CorruptState(f"{path}: {e}") from e

    def read_origin(self) -> dict[str, str] | None:
        return self._read(ORIGIN)

    def write_origin(self, origin: dict[str, str]) -> None:
        write_json_atomically(origin, self.dir / ORIGIN)

    def load_snapshot(self) -> dict[str, Any] | None:
        return self._read(SNAPSHOT)

    def replay_journal(self, snapshot_seq: int, replay: Callable[[dict[str, Any]], None]) -> int:
        """Feed every journaled delta after ``snapshot_seq`` to ``replay``; returns how many."""
        path = self.dir / JOURNAL
        if not path.exists():
            return 0
        count = 0
        good_bytes = 0
        with open(path, "rb") as f:
            lines = f.readlines()
        for i, raw in enumerate(lines):
            try:
                delta = json.loads(raw)
            except json.JSONDecodeError:
                if i == len(lines) - 1:  # torn tail: never acknowledged, never broadcast
                    msg = (
                        f"{path}: dropping a torn last line of {len(raw)} bytes "
                        "(a write cut by a crash)"
                    )
                    log.warning(msg)
                    self.warnings.append(msg)
                    with open(path, "r+b") as f:
                        f.truncate(good_bytes)
                    break
                raise CorruptState(f"{path}: line {i + 1} is not JSON") from None
            good_bytes += len(raw)
            if delta.get("seq", 0) <= snapshot_seq:
                continue
            try:
                replay(delta)
            except Exception as e:  # a journal that does not replay is a bug or a damaged disk
                raise CorruptState(
                    f"{path}: line {i + 1} (seq {delta.get('seq')}) does not replay: {e}"
                ) from e
            count += 1
        self._since_compaction = count
        if count:  # lines a killed server wrote but never synced: durable from now on
            with open(path, "rb") as f:
                os.fdatasync(f.fileno())
        return count

    # ------------------------------------------------------------------ writing
    def append(self, delta: dict[str, Any]) -> None:
        """Write a delta to the journal (durable after ``flush``)."""
        self._open_journal().write(compact(delta) + "\n")
        self._since_compaction += 1

    def write_lines(self, lines: list[str]) -> None:
        """Journal lines (each a delta and its newline), durable when this returns."""
        self._open_journal().write("".join(lines))
        self._since_compaction += len(lines)
        self.flush()

    def _open_journal(self):
        if self._journal is None:
            self._journal = open(self.dir / JOURNAL, "a", encoding="utf-8")
        return self._journal

    def flush(self) -> None:
        if self._journal is not None:
            self._journal.flush()
            os.fdatasync(self._journal.fileno())

    def needs_compaction(self) -> bool:
        return self._since_compaction >= self.compact_every

    def write_snapshot(self, snapshot: dict[str, Any]) -> None:
        """Make ``snapshot`` the durable state and start an empty journal after it."""
        self.flush()
        write_json_atomically(snapshot, self.dir / SNAPSHOT, indent=None)
        dir_fd = os.open(self.dir, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)
        if self._journal is not None:
            self._journal.close()
        self._journal = open(self.dir / JOURNAL, "w", encoding="utf-8")
        self._since_compaction = 0
