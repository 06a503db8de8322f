"""Fast DDS's shared-memory files left by processes that died without closing them, found and
removed without racing the living.

Fast DDS keeps in /dev/shm a segment per participant (``fastrtps_<16 chars>``, with an ``_el``
lock file its owner holds while alive) and a port per locator (``fastrtps_port<N>``, the ``_el``
or ``_sl`` lock file its listeners hold, ``sem.fastrtps_port<N>_mutex``). A process killed
outright leaves them, and a stale port can hang a later participant at start (Fast-DDS issues
1144, 6117). ``fastdds shm clean`` tells a dead file by taking its lock and removes every file
whose lock it could take: a participant locking a port at that moment fails ("Failed init_port
... open_and_lock_file failed", what a CI run's Panel printed before it never joined the DSR,
beside tests that ran the tool), and a port made but not yet locked is removed under its maker.
Here a lock is read from /proc/locks, never taken; a segment (named by a random id, never
reused) goes when no process holds its lock and it is older than a minute; a port only in the
ROS domains the caller names, when no process listens on it and it is older than ten seconds
(a process starting in that domain makes and locks its port's files in a moment)."""

from __future__ import annotations

import os
import re
import time
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

SHM_DIR = Path("/dev/shm")
# a file is made and locked within a moment: one this old that no process holds is dead
SEGMENT_MIN_AGE = 60.0
PORT_MIN_AGE = 10.0
# RTPS well-known ports (DDS-RTPS 9.6.1.1): a domain's are PB + DG * domain and the DG after it
PORT_BASE, DOMAIN_GAIN = 7400, 250

_SEGMENT = re.compile(r"^fastrtps_([0-9a-z]{16})(_el|_sl)?$")
_PORT = re.compile(r"^(?:sem\.)?fastrtps_port(\d+)(_el|_sl|_mutex)?$")
_LOCK = re.compile(r"\b([0-9a-f]+):([0-9a-f]+):(\d+)\b")


@dataclass(frozen=True)
class ShmFile:
    name: str
    file_id: tuple[int, int, int]  # (device major, minor, inode): how /proc/locks names a file
    mtime: float


def held_locks(proc_locks: str) -> set[tuple[int, int, int]]:
    """The files some process holds a lock on, from the text of /proc/locks."""
    held = set()
    for line in proc_locks.splitlines():
        found = _LOCK.search(line)
        if found:
            held.add((int(found[1], 16), int(found[2], 16), int(found[3])))
    return held


def domain_ports(domain: int) -> range:
    return range(PORT_BASE + DOMAIN_GAIN * domain, PORT_BASE + DOMAIN_GAIN * (domain + 1))


def zombies(
    files: list[ShmFile],
    held: set[tuple[int, int, int]],
    domains: list[int] = (),
    now: float | None = None,
    min_age: dict[str, float] | None = None,
) -> list[str]:
    """The names among ``files`` that belong to no living process: segments, and ports of
    ``domains``, that no process holds locked and that are older than ``min_age`` (seconds, by
    kind: "segment", "port")."""
    min_age = min_age or {"segment": SEGMENT_MIN_AGE, "port": PORT_MIN_AGE}
    now = time.time() if now is None else now
    ports = {p for d in domains for p in domain_ports(d)}
    groups: dict[tuple[str, str], list[ShmFile]] = defaultdict(list)
    for f in files:
        segment, port = _SEGMENT.match(f.name), _PORT.match(f.name)
        if segment:
            groups["segment", segment[1]].append(f)
        elif port and int(port[1]) in ports:
            groups["port", port[1]].append(f)
    dead = []
    for (kind, _), group in groups.items():
        if any(f.file_id in held for f in group):
            continue
        if any(now - f.mtime < min_age[kind] for f in group):
            continue
        dead.extend(f.name for f in group)
    return sorted(dead)


def _listing(shm_dir: Path) -> list[ShmFile]:
    files = []
    for path in shm_dir.glob("*fastrtps_*"):
        try:
            st = path.stat()
        except FileNotFoundError:  # its process removed it as we looked
            continue
        file_id = (os.major(st.st_dev), os.minor(st.st_dev), st.st_ino)
        files.append(ShmFile(path.name, file_id, st.st_mtime))
    return files


def clean(domains: list[int] = (), shm_dir: Path = SHM_DIR) -> list[str]:
    """Remove the dead files (``zombies``) in ``shm_dir``; returns their names. Nothing is
    removed where /proc/locks cannot be read (every file would look dead)."""
    try:
        held = held_locks(Path("/proc/locks").read_text())
    except OSError:
        return []
    removed = []
    for name in zombies(_listing(shm_dir), held, list(domains)):
        try:
            (shm_dir / name).unlink()
            removed.append(name)
        except FileNotFoundError:
            pass
    return removed
