"""Each RT edge's recent transforms with their times, so that a chain can be asked "at time t"
(CORTEX's RT history; the Get Up & Go asks where the pelvis was when). Pure (numpy, transforms3d).

A value's time is that of the delta that wrote it (the server's ``stamp``), so the server and
every replica keep the same history. Per edge at most ``max_count`` values, and none older than
``max_age`` seconds behind its newest but the one that was current then. An edge known before
its first change here (loaded from a world, a snapshot) keeps that value as held "since ever"
until the bounds push it out. Between two values a pose is interpolated: translation linearly,
rotation along the shortest arc (slerp); after the newest, the newest holds; before the oldest
kept, the time is refused by name (``OutsideHistory``).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
from transforms3d import quaternions

from dsr_graph.exceptions import OutsideHistory

EdgeKey = tuple[int, int, str]
SINCE_EVER = -math.inf
DEFAULT_MAX_AGE = 10.0  # seconds
DEFAULT_MAX_COUNT = 100  # values per edge: 3.3 s of a 30 Hz skeleton, 10 s of anything slower


class RtHistory:
    def __init__(self, max_age: float = DEFAULT_MAX_AGE, max_count: int = DEFAULT_MAX_COUNT):
        self._values: dict[EdgeKey, deque[tuple[float, np.ndarray]]] = {}
        self.limit(max_age, max_count)

    def limit(self, max_age: float, max_count: int) -> None:
        """Bound what is kept (from the next value recorded on)."""
        if isinstance(max_age, bool) or not isinstance(max_age, (int, float)) or not max_age > 0:
            raise ValueError(f"the RT history's max_age must be seconds > 0, got {max_age!r}")
        if isinstance(max_count, bool) or not isinstance(max_count, int) or max_count < 2:
            raise ValueError(
                f"the RT history's max_count must be an integer >= 2, got {max_count!r}"
            )
        self.max_age = float(max_age)
        self.max_count = max_count

    def before_change(self, key: EdgeKey, matrix: np.ndarray) -> None:
        """An edge's transform is about to change: what it held until now is kept, if it is the
        first change of it here."""
        if key not in self._values:
            self._values[key] = deque([(SINCE_EVER, matrix)])

    def record(self, key: EdgeKey, when: float, matrix: np.ndarray) -> None:
        values = self._values.setdefault(key, deque())
        if values and when < values[-1][0]:
            when = values[-1][0]  # a clock stepped back: times never go back in a history
        values.append((when, matrix))
        while len(values) > self.max_count:
            values.popleft()
        cutoff = when - self.max_age
        while len(values) > 1 and values[1][0] <= cutoff:
            values.popleft()

    def forget(self, keys: Iterable[EdgeKey]) -> None:
        for key in keys:
            self._values.pop(key, None)

    def keys(self) -> list[EdgeKey]:
        return list(self._values)

    def span(self, key: EdgeKey) -> tuple[float, float] | None:
        """(oldest, newest) time kept for the edge; None for an edge never changed here."""
        values = self._values.get(key)
        return (values[0][0], values[-1][0]) if values else None

    def matrix_at(self, key: EdgeKey, current: np.ndarray, when: float, label: str) -> np.ndarray:
        values = self._values.get(key)
        if not values or when >= values[-1][0]:
            return current  # never changed here, or held since its newest value
        if when < values[0][0]:
            raise OutsideHistory(
                f"{label}: no transform at {when:.3f}: its history holds {values[0][0]:.3f} to "
                f"{values[-1][0]:.3f} (at most {self.max_count} values, {self.max_age:g} s)"
            )
        # the last value at or before ``when`` (few values: a scan from the newest end)
        i = len(values) - 1
        while values[i][0] > when:
            i -= 1
        (t0, m0), (t1, m1) = values[i], values[i + 1]
        if t0 == SINCE_EVER or t1 == t0:
            return m0
        return interpolate(m0, m1, (when - t0) / (t1 - t0))


def interpolate(m0: np.ndarray, m1: np.ndarray, f: float) -> np.ndarray:
    """The pose a fraction ``f`` of the way from ``m0`` to ``m1``."""
    q0, q1 = quaternions.mat2quat(m0[:3, :3]), quaternions.mat2quat(m1[:3, :3])
    if np.dot(q0, q1) < 0:
        q1 = -q1  # the shortest arc
    axis, angle = quaternions.quat2axangle(quaternions.qmult(quaternions.qinverse(q0), q1))
    step = quaternions.axangle2quat(axis, angle * f) if angle else np.array([1.0, 0, 0, 0])
    out = np.eye(4)
    out[:3, :3] = quaternions.quat2mat(quaternions.qmult(q0, step))
    out[:3, 3] = (1 - f) * m0[:3, 3] + f * m1[:3, 3]
    return out


def remember(graph: Any, ops: Iterable[Mapping[str, Any]], when: Any) -> None:
    """Keep the transforms ``ops`` (canonical, applied to ``graph``) wrote, at ``when``; forget
    the edges they deleted."""
    if isinstance(when, bool) or not isinstance(when, (int, float)):
        return
    history: RtHistory = graph.rt_history
    deleted_node = False
    for op in ops:
        kind = op["op"]
        if kind == "set_rt" or (kind == "insert_edge" and "rt" in op):
            src, dst = graph.find(op["from"]), graph.find(op["to"])
            edge = None if src is None or dst is None else graph.edge(src.id, dst.id, "RT")
            if edge is not None:
                history.record(edge.key, float(when), edge.rt)
        elif kind == "delete_edge" and op["type"] == "RT":
            deleted_node = True  # its ends are names: check which kept edges are gone
        elif kind == "delete_node":
            deleted_node = True
    if deleted_node:
        history.forget(k for k in history.keys() if graph.edge(*k) is None)
