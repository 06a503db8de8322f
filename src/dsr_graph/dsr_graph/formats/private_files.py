"""Patients' data at rest: every process of the suite starts with ``set_private_umask()``, so
what it creates (state directories, journals, the results store, logs, recordings, outboxes) is
0600/0700, readable by its user only. Nothing changes the umask after that: reading it goes
through /proc, never through ``os.umask``'s set-and-restore (a window in which another thread's
files would be created world-writable)."""

from __future__ import annotations

import os
from pathlib import Path

PRIVATE_UMASK = 0o077


def set_private_umask() -> None:
    os.umask(PRIVATE_UMASK)


def current_umask() -> int:
    """The process's umask, read without changing it (Linux 4.7+); the private one if unknown."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    return PRIVATE_UMASK


def private_dir(path: os.PathLike | str) -> Path:
    """``path`` made (with its parents) and closed to others: a directory the suite owns alone
    (a state directory, an outbox, a keystore's private keys), also when an older version
    created it open."""
    path = Path(path)
    path.mkdir(mode=0o700, parents=True, exist_ok=True)
    os.chmod(path, 0o700)
    return path


def write_private(path: os.PathLike | str, data: bytes) -> None:
    """``data`` as the file ``path``, 0600 from its first byte (a key, a secret): written to a
    new file beside it, synced, then renamed over it, so a crash leaves the old file or the new
    one, never a part of one, nor one that others could read for a moment."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    try:
        os.write(fd, data)
        os.fsync(fd)
    finally:
        os.close(fd)
    os.replace(tmp, path)
