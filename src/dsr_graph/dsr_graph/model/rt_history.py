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

import bisect
import math
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np
from transforms3d import quaternions

from dsr_graph.exceptions import OutsideHistory

EdgeKey = tuple[int, int, str]
SINCE_EVER = -math.inf
DEFAULT_MAX_AGE = 10.0  # seconds
DEFAULT_MAX_COUNT = 100  # values per edge: 3.3 s of a 30 Hz skeleton, 10 s of anything slower


class _Values:
    """One edge's kept values, oldest first: times, matrices, and each rotation's quaternion
    once it was needed (interpolation)."""

    __slots__ = ("times", "poses", "quats")

    def __init__(self) -> None:
        self.times: list[float] = []
        self.poses: list[np.ndarray] = []
        self.quats: list[np.ndarray | None] = []

    def append(self, when: float, matrix: np.ndarray) -> None:
        self.times.append(when)
        self.poses.append(matrix)
        self.quats.append(None)

    def drop_oldest(self, n: int) -> None:
        del self.times[:n], self.poses[:n], self.quats[:n]

    def quat(self, i: int) -> np.ndarray:
        q = self.quats[i]
        if q is None:
            q = self.quats[i] = quaternions.mat2quat(self.poses[i][:3, :3])
        return q


class RtHistory:
    def __init__(self, max_age: float = DEFAULT_MAX_AGE, max_count: int = DEFAULT_MAX_COUNT):
        self._values: dict[EdgeKey, _Values] = {}
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
            values = self._values[key] = _Values()
            values.append(SINCE_EVER, matrix)

    def record(self, key: EdgeKey, when: float, matrix: np.ndarray) -> None:
        values = self._values.get(key)
        if values is None:
            values = self._values[key] = _Values()
        if values.times and when < values.times[-1]:
            when = values.times[-1]  # a clock stepped back: times never go back in a history
        values.append(when, matrix)
        times = values.times
        # at most max_count; none older than max_age behind the newest but the one current then
        drop = max(0, len(times) - self.max_count)
        cutoff = when - self.max_age
        while drop + 1 < len(times) and times[drop + 1] <= cutoff:
            drop += 1
        if drop:
            values.drop_oldest(drop)

    def forget(self, keys: Iterable[EdgeKey]) -> None:
        for key in keys:
            self._values.pop(key, None)

    def keys(self) -> list[EdgeKey]:
        return list(self._values)

    def span(self, key: EdgeKey) -> tuple[float, float] | None:
        """(oldest, newest) time kept for the edge; None for an edge never changed here."""
        values = self._values.get(key)
        return (values.times[0], values.times[-1]) if values else None

    def matrix_at(
        self, key: EdgeKey, current: np.ndarray, when: float, label: Callable[[], str]
    ) -> np.ndarray:
        """The edge's transform at ``when``; ``label()`` names the edge in a refusal."""
        values = self._values.get(key)
        if values is None or when >= values.times[-1]:
            return current  # never changed here, or held since its newest value
        times = values.times
        if when < times[0]:
            raise OutsideHistory(
                f"{label()}: no transform at {when:.3f}: its history holds {times[0]:.3f} to "
                f"{times[-1]:.3f} (at most {self.max_count} values, {self.max_age:g} s)"
            )
        i = bisect.bisect_right(times, when) - 1  # the last value at or before ``when``
        t0, t1 = times[i], times[i + 1]
        if t0 == SINCE_EVER or t1 == t0:
            return values.poses[i]
        f = (when - t0) / (t1 - t0)
        return _between(values.poses[i], values.poses[i + 1], values.quat(i), values.quat(i + 1), f)


def interpolate(m0: np.ndarray, m1: np.ndarray, f: float) -> np.ndarray:
    """The pose a fraction ``f`` of the way from ``m0`` to ``m1``."""
    q0, q1 = quaternions.mat2quat(m0[:3, :3]), quaternions.mat2quat(m1[:3, :3])
    return _between(m0, m1, q0, q1, f)


def _between(m0: np.ndarray, m1: np.ndarray, q0: np.ndarray, q1: np.ndarray, f: float):
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
    pruned = False
    for op in ops:
        kind = op["op"]
        if kind == "set_rt" or (kind == "insert_edge" and "rt" in op):
            edge = graph.edge(op["from"], op["to"], "RT")  # None if a later op deleted it
            if edge is not None:
                history.record(edge.key, float(when), edge.rt)
        elif kind == "delete_edge" and op["type"] == "RT":
            pruned = True  # its ends are names: check which kept edges are gone
        elif kind == "delete_node":
            pruned = True
    if pruned:
        history.forget(k for k in history.keys() if graph.edge(*k) is None)
