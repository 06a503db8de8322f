"""Bulk work with CPython's cyclic garbage collector paused, and bulk kept out of its reach.

Parsing, building or encoding a whole snapshot allocates millions of containers at once; the
collector runs a young collection every 700 of them and, as the heap grows, full ones that walk
all of it. A 100k-node snapshot parsed and rebuilt took 1.8 s with it and 0.95 s without
(bench/run.py's scale world). Nothing these steps build holds a cycle to reclaim; the collector
resumes afterwards.

What such a step leaves is then most of the process, and every later collection of the older
generations would walk it (0.57 s for a replica of 100k nodes, a stall some time after joining):
``settle()`` moves it out of the collector's reach. Reference counting still frees it (a
replica's graph holds no reference cycle; test_lazy_replica checks an old one is freed). Pure.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def collector_paused() -> Iterator[None]:
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def settle() -> None:
    """Everything the process holds now is long-lived: never walked by a collection again."""
    gc.freeze()
