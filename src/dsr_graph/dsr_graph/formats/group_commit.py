"""The journal's group commit: visible first, durable before acknowledged.

The server's thread encodes each accepted symbolic delta into a buffer and goes on to broadcast
it; a commit thread writes whatever has gathered and makes it durable with one fdatasync, then
says up to which seq (``on_durable``, called in the commit thread). While the disk syncs, the
server keeps accepting: the next commit takes everything that came meanwhile, so under load one
fdatasync covers many deltas.

The bytes reach the file only in a commit, so a server killed between broadcast and commit loses
the deltas after the last durable seq, which nobody was told were durable: their writers' verdicts
wait for it, and the replicas that saw them resync with the restarted server
(protocol/agent_core.py). If the disk fails the server cannot keep its word: ``on_failure`` is
called with the error and the thread stops committing.

    commit = GroupCommit(store, durable=core.seq, on_durable=tell, on_failure=die)
    commit.start()
    commit.append(delta)          # the server's thread, before broadcasting it
    commit.compact(snapshot)      # the server's thread: the snapshot becomes the durable state
    commit.close()                # what gathered is committed, the thread ends
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from dsr_graph.formats.state_store import StateStore
from dsr_graph.model.binary import compact

STOP_TIMEOUT = 10.0  # seconds close() waits for a commit in progress


class GroupCommit:
    def __init__(
        self,
        store: StateStore,
        durable: int,
        on_durable: Callable[[int], None] = lambda seq: None,
        on_failure: Callable[[OSError], None] = lambda error: None,
        delay: float = 0.0,
    ):
        """``durable``: the seq on disk already (the restored state's). ``delay``: seconds a
        commit waits for more deltas after the first one came (0: none; PostgreSQL's
        commit_delay): fewer fdatasyncs under load, longer verdicts."""
        self.store = store
        self.delay = delay
        self.on_durable = on_durable
        self.on_failure = on_failure
        self._durable = durable
        self._lines: list[str] = []
        self._last = durable  # seq of the last delta appended
        self._gathered = threading.Condition()
        self._io = threading.Lock()  # one writer of the files at a time: a commit, a compaction
        self._stopping = False
        self._thread: threading.Thread | None = None
        self.failed: OSError | None = None

    @property
    def durable(self) -> int:
        """The highest seq on disk: every accepted delta up to it survives any crash."""
        return self._durable

    @property
    def pending(self) -> int:
        """Deltas appended and not yet durable."""
        return self._last - self._durable

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="dsr-group-commit", daemon=True)
        self._thread.start()

    def append(self, delta: dict[str, Any]) -> None:
        """A symbolic delta, accepted, in seq order: encoded now, durable at the next commit."""
        line = compact(delta) + "\n"
        with self._gathered:
            self._lines.append(line)
            self._last = delta["seq"]
            self._gathered.notify()

    def commit(self) -> int:
        """Write and sync what has gathered, in the caller's thread; returns the durable seq.
        Raises OSError if the disk fails (nothing is said durable then)."""
        with self._io:
            return self._commit_locked()

    def _commit_locked(self) -> int:
        with self._gathered:
            lines, self._lines = self._lines, []
            last = self._last
        if lines:
            self.store.write_lines(lines)
            self._durable = last
            self.on_durable(last)
        return self._durable

    def compact(self, snapshot: dict[str, Any]) -> None:
        """Make ``snapshot`` (the state at the last seq appended: take it in the thread that
        appends) the durable state, with an empty journal after it."""
        with self._io:
            self._commit_locked()
            self.store.write_snapshot(snapshot)

    def close(self) -> None:
        """Commit what has gathered and end the thread (a clean stop loses nothing)."""
        with self._gathered:
            self._stopping = True
            self._gathered.notify()
        if self._thread is not None:
            self._thread.join(STOP_TIMEOUT)
        if self.failed is None:
            self.commit()

    def _run(self) -> None:
        while True:
            with self._gathered:
                while not self._lines and not self._stopping:
                    self._gathered.wait()
                if self._stopping:
                    return  # close() commits the rest in its own thread
                if self.delay > 0:  # more may come: one fdatasync for all of them
                    self._gathered.wait_for(lambda: self._stopping, self.delay)
            try:
                self.commit()
            except OSError as e:
                self.failed = e
                self.on_failure(e)
                return
