"""How a rendering process keeps its memory: the server's, and every Dask worker's.

A 1024x1024 job passes about 40 MB of short-lived buffers through the process
(tile layers, their RGBA8, stream messages, the job's image). With glibc's
defaults each megabyte-sized buffer is returned to the kernel when freed
(mmap, or trimmed off the top of a heap) and faulted in again, page by page
and zeroed, the next time: about 5,300 page faults per image, and numpy's
huge-page advice on arrays over 4 MB made its faults zero 2 MB each. That was
16% of the event loop's time and about 5% of the whole job's CPU. Keeping freed
memory in the heap for reuse costs at most the peak a job needed.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import logging

import numpy as np

log = logging.getLogger("rt.allocator")

# glibc's mallopt parameters (malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
MMAP_THRESHOLD = 32 << 20    # glibc's largest: buffers up to 32 MB come from the heap
TRIM_THRESHOLD = 512 << 20   # free heap kept for reuse before any is returned


def keep_freed_memory() -> bool:
    """Tunes this process's allocator as above; False where it is not glibc's."""
    try:
        # A private switch, but numpy's own: it is what NUMPY_MADVISE_HUGEPAGE=0 sets.
        np._core.multiarray._set_madvise_hugepage(False)
    except AttributeError:
        log.debug("numpy has no huge-page switch")
    name = ctypes.util.find_library("c")
    libc = ctypes.CDLL(name) if name else None
    mallopt = getattr(libc, "mallopt", None)
    if mallopt is None:
        return False
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD))
