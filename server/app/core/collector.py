"""The cyclic garbage collector, kept from pausing the event loop.

A full (generation 2) collection walks every object the process tracks, and
most of them were made once, at start-up: modules, FastAPI's routes and models,
Dask's scheduler and worker, protobuf's descriptors. Under the load benchmark
(tests/bench/load_bench.py) one ran every second or two and held the event
loop for 70-90 ms each time, which made the slowest 1% of answers. Frozen
(gc.freeze, as CPython's docs suggest for servers), the start-up objects are
left out of every walk.

What is left is garbage made in cycles, and the embedded Dask cluster makes
plenty: each of its batched streams waits for its next send with a timeout,
and every expiry leaves a TimeoutError, its traceback and frames in a cycle,
some 60,000 objects a second under that load. Collecting young objects every
10,000 allocations instead of every 700 makes the full collections, which walk
all that survives, ten times rarer. Measured in turns, three runs each, p99
of the reads at a post every 0.5 s per client (more than the cluster renders):
88-129 ms, against 159-274 ms with CPython's thresholds; at a post a second,
both 26-48 ms.
"""

from __future__ import annotations

import gc

# Allocations between young collections, then young collections between
# middle ones, and middle ones between full ones (CPython's: 700, 10, 10).
THRESHOLDS = (10_000, 10, 10)


def settle_after_startup() -> int:
    """Collects once, leaves everything alive now out of later collections,
    and sets THRESHOLDS; how many objects were frozen."""
    gc.collect()
    gc.freeze()
    gc.set_threshold(*THRESHOLDS)
    return gc.get_freeze_count()

