"""The garbage-collector policy of a DSR process, set once where the process starts (``run_node``,
``dsr``), never switched on and off by the pure code.

A DSR process encodes, parses and builds whole snapshots: millions of containers at once, none
holding a cycle. With CPython's default thresholds (a young collection every 700 new
containers) a 100k-node snapshot took 1.12 s to encode and 1.14 s to load into a replica; with
the young threshold at 100,000 (set here), 0.74 s and 0.77 s (``scripts/bench.sh --only gc``,
interleaved rounds; against the collector paused around each bulk step, as before: encode 1.05x,
load 0.96x; BENCHMARKS.md). Cyclic garbage is still collected, later.

What a replica loads is then most of the process: ``settle`` (after each snapshot a replica
loads) moves it out of reach of the full collections that would walk it again (0.57 s for a
100k-node replica). Reference counting still frees it: a replica's graph holds no cycle
(test_lazy_replica).
"""

from __future__ import annotations

import gc

THRESHOLDS = (100_000, 50, 100)  # young collection every 100k new containers; then CPython's


def use_dsr_policy() -> None:
    gc.set_threshold(*THRESHOLDS)


def settle() -> None:
    """Everything the process holds now is long-lived: never walked by a collection again."""
    gc.freeze()
